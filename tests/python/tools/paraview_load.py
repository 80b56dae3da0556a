"""Run by pvbatch (tests/python/test_paraview.py): loads an XDMF file the
way a ParaView user does and prints what each reader saw, as JSON.

    pvbatch paraview_load.py FILE.xdmf [PICTURE.png]

With PICTURE, the last time step is rendered as Points coloured by pressure
(what docs/results-files.md shows)."""
import json
import sys

from paraview import simple


def describe(reader):
    out = {"times": list(reader.TimestepValues)}
    steps = []
    for t in out["times"]:
        reader.UpdatePipeline(t)
        info = reader.GetDataInformation()
        steps.append({"time": t, "points": info.GetNumberOfPoints(),
                      "cells": info.GetNumberOfCells(), "type": info.GetDataSetTypeAsString()})
    out["steps"] = steps
    out["point_arrays"] = sorted(reader.PointData.keys())
    pressure = reader.PointData["pressure"].GetRange() if "pressure" in reader.PointData.keys() \
        else None
    out["pressure_range"] = list(pressure) if pressure else None
    return out


def main():
    path = sys.argv[1]
    seen = {}
    for name in ("Xdmf3ReaderS", "Xdmf3ReaderT"):
        seen[name] = describe(getattr(simple, name)(FileName=[path]))
    seen["XDMFReader"] = describe(simple.XDMFReader(FileNames=[path]))
    if len(sys.argv) > 2:
        reader = simple.Xdmf3ReaderS(FileName=[path])
        view = simple.CreateView("RenderView")
        view.ViewSize = [900, 700]
        if hasattr(view, "UseColorPaletteForBackground"):  # ParaView >= 5.10
            view.UseColorPaletteForBackground = 0
        view.Background = [1, 1, 1]
        view.OrientationAxesVisibility = 0
        view.ViewTime = reader.TimestepValues[-1]
        shown = simple.Show(reader, view)
        shown.SetRepresentationType("Points")
        shown.PointSize = 4
        simple.ColorBy(shown, ("POINTS", "pressure"))
        shown.RescaleTransferFunctionToDataRange(True, False)
        shown.SetScalarBarVisibility(view, True)
        bar = simple.GetScalarBar(simple.GetColorTransferFunction("pressure"), view)
        bar.Title, bar.ComponentTitle = "pressure (Pa)", ""
        bar.TitleColor = bar.LabelColor = [0, 0, 0]
        text = simple.Text(Text="t = %.3f s" % reader.TimestepValues[-1])
        label = simple.Show(text, view)
        label.Color, label.WindowLocation = [0, 0, 0], "Upper Center"
        view.InteractionMode = "2D"
        simple.ResetCamera(view)
        simple.SaveScreenshot(sys.argv[2], view, ImageResolution=[900, 700])
    print("PARAVIEW " + json.dumps(seen))


main()
