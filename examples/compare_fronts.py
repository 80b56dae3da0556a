"""The surge front of two runs of `mps2p run` (their series.csv, probe
"front") against each other and Martin & Moyce (1952): the main job's
two-phase dam break beside the water-only one.

    python3 examples/compare_fronts.py RUN OTHER OUT.png [--labels A B]

RUN and OTHER are output folders of `mps2p run`; the column width (its front
probe) and the walls (its first tank) are read from RUN's scene."""
import argparse
import csv
import json
import os

import numpy as np

from mps2p.tools.pictures import front_picture
from mps2p.tools.scenefile import load


def front_series(folder):
    with open(os.path.join(folder, "series.csv")) as f:
        rows = list(csv.DictReader(f))
    return np.array([[float(r["time"]), float(r["front"])] for r in rows])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run")
    parser.add_argument("other")
    parser.add_argument("out")
    parser.add_argument("--labels", nargs=2, default=["water and air", "water only"])
    args = parser.parse_args()
    with open(os.path.join(args.run, "summary.json")) as f:
        scene = load(json.load(f)["scene"])
    probe = next(p for p in scene.probes if p["name"] == "front")
    tank = scene.data["tank"][0]["box"]  # as mps2p run's front.png
    front_picture(args.out, front_series(args.run), probe["column_width"], scene.name,
                  origin=tank[0], wall=tank[2], label=args.labels[0],
                  others=[(args.labels[1], front_series(args.other))], spacing=scene.l0)
    print("front picture:", args.out)


if __name__ == "__main__":
    main()
