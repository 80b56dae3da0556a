"""The pictures of `mps2p run`, inspected as the figures matplotlib drew
(issue 19): units on every axis, titles inside the figure, the wall and the
experiment on the front, t = 0 in every snapshot picture, and each fluid
with its own colour scale."""
import os
import re

import numpy as np
import pytest

from mps2p.tools import pictures
from mps2p.tools.run import run

from conftest import SCENES


@pytest.fixture
def figures(monkeypatch):
    """Every figure the pictures module closes, kept for inspection."""
    kept = []
    close = pictures.plt.close

    def keep(fig=None):
        kept.append(fig)
        fig.canvas.draw()  # lays the text out, as savefig did

    monkeypatch.setattr(pictures.plt, "close", keep)
    yield kept
    for fig in kept:
        close(fig)


def by_file(figures, tmp_path, names):
    """{png name: figure}, in the order run() writes them."""
    written = [n for n in names if (tmp_path / n).exists()]
    assert len(written) == len(figures), (written, len(figures))
    return dict(zip(written, figures))


def fits(fig, text):
    """The text lies inside the figure's width."""
    box = text.get_window_extent(renderer=fig.canvas.get_renderer())
    return box.x0 >= 0 and box.x1 <= fig.bbox.width


def every_axis_has_a_unit(fig):
    """Each y axis and colour bar is labelled with a unit, and so is every x
    label (panels that share x with the one below have none)."""
    xlabels = []
    for ax in fig.axes:
        if not ax.axison:
            continue
        if ax.get_label() == "<colorbar>":  # one label, along the bar
            labels = [label for label in (ax.get_xlabel(), ax.get_ylabel()) if label]
        else:
            labels = [ax.get_ylabel()] + ([ax.get_xlabel()] if ax.get_xlabel() else [])
            xlabels.append(ax.get_xlabel())
        for label in labels:
            assert "(" in label and ")" in label, "no unit in %r" % label
    assert any(xlabels)


def test_dam_break_pictures(figures, tmp_path):
    run(os.path.join(SCENES, "dam_break.toml"), str(tmp_path), until=0.5)
    drawn = by_file(figures, tmp_path, ["snapshots.png", "series.png", "front.png"])
    for name, fig in drawn.items():
        every_axis_has_a_unit(fig)
        titles = [fig._suptitle] if fig._suptitle else [fig.axes[0].title]
        assert all(fits(fig, t) for t in titles), name
    panels = [ax.get_title() for ax in drawn["snapshots.png"].axes if ax.get_title()]
    assert panels[0] == "t = 0.000 s" and panels[-1] == "t = 0.500 s"
    series = drawn["series.png"].axes
    assert "surge front x (m)" in series[0].get_ylabel()
    assert "pressure at (0.595, 0.005) m (Pa)" in series[1].get_ylabel()
    assert "kinetic_energy (J/m)" in series[2].get_ylabel()
    front = drawn["front.png"].axes[0]
    wall = [line for line in front.get_lines() if "opposite wall" in line.get_label()]
    assert wall and set(wall[0].get_ydata()) == {4.0}  # 0.6 m / 0.15 m
    assert front.get_ylim()[1] <= 1.1 * 4.0 + 1e-9  # not the reference's Z = 14.5
    assert any("Martin & Moyce" in line.get_label() for line in front.get_lines())
    simulated = [line for line in front.get_lines() if line.get_label() == "libmps2p"][0]
    assert max(simulated.get_ydata()) <= 4.0 + 0.1  # stops at the wall


def test_two_fluid_pictures_tell_them_apart(figures, tmp_path):
    text = open(os.path.join(SCENES, "ikari2003_dam_break_air.toml")).read()
    assert "l0 = 0.01\n" in text and text.count("picture_times = [") == 1
    text = re.sub(r"picture_times = \[[^\]]*\]", "picture_times = [0.01, 0.5]",
                  text.replace("l0 = 0.01\n", "l0 = 0.02\n"))
    scene = tmp_path / "air.toml"
    scene.write_text(text)
    out = tmp_path / "out"
    run(str(scene), str(out), until=0.02)
    drawn = by_file(figures, out, ["snapshots.png", "snapshots_phase.png", "velocity_air.png",
                                   "series.png", "front.png"])
    for name, fig in drawn.items():
        titles = [fig._suptitle] if fig._suptitle else [fig.axes[0].title]
        assert all(fits(fig, t) for t in titles), name
        every_axis_has_a_unit(fig)
    for name in ("snapshots.png", "snapshots_phase.png", "velocity_air.png"):
        panels = [ax.get_title() for ax in drawn[name].axes if ax.get_title().startswith("t =")]
        # t = 0, the one asked time before the end, and the end --until cut it to
        assert panels == ["t = 0.000 s", "t = 0.010 s", "t = 0.020 s"], (name, panels)
    bars = [ax.get_ylabel() for ax in drawn["snapshots.png"].axes
            if ax.get_ylabel().endswith("pressure (Pa)")]
    assert bars == ["water pressure (Pa)", "air pressure (Pa)"]


def test_the_front_curve_ends_where_the_water_first_touches_the_wall():
    # the paper's case: a = 0.15 m, wall 0.6 m, l0 = 0.01 m; the front (largest x
    # + l0/2) touched the wall at 0.596 m, fell back to 0.585 m and came again:
    # the curve used to run on past that first touch (a margin of 0.02 in Z,
    # 3 mm, under the gap the water keeps at the wall)
    t = np.array([0.20, 0.25, 0.26, 0.27, 0.28, 0.30])
    x = np.array([0.50, 0.58, 0.596, 0.585, 0.597, 0.599])
    T, Z = pictures._front_curve(np.column_stack([t, x]), 0.15, 0.0, 4.0, 9.81, 0.01)
    assert len(Z) == 3 and Z[-1] == pytest.approx(0.596 / 0.15)
    # a front not yet at the wall is drawn whole, its missing samples left out
    x_early = np.array([np.nan, 0.2, 0.3, 0.4, 0.5, 0.55])
    T, Z = pictures._front_curve(np.column_stack([t, x_early]), 0.15, 0.0, 4.0, 9.81, 0.01)
    assert len(Z) == 5 and np.all(np.isfinite(Z))
