"""The C example's surge front against Martin & Moyce (1952), drawn by the
same function as `mps2p run`'s front.png (mps2p.tools.pictures.front_picture).

    ./build/examples/dam_break 0.01 1.0 OUT_DIR/run.h5 > OUT_DIR/front.txt
    python3 examples/plot_dam_break.py OUT_DIR [L0]

reads OUT_DIR/front.txt (columns t, T, Z, steps; L0 the run's spacing, 0.01 m
unless given), writes OUT_DIR/front.png and
prints the front's error against the a = 2.25 in series. (`mps2p run
dam_break` draws its own front.png: this script is for the C example.)"""
import os
import sys

import numpy as np

from mps2p.tools.pictures import front_picture, martin_moyce

A = 0.15  # column width (m)
TANK = 0.6  # the opposite wall (m)


def main(out, spacing=0.01):
    t, _, Z = np.loadtxt(os.path.join(out, "front.txt"), comments="#", unpack=True)[:3]
    front_picture(os.path.join(out, "front.png"), np.column_stack([t, Z * A]), A,
                  "dam break from C (examples/dam_break.c)", origin=0.0, wall=TANK,
                  spacing=spacing)
    ref_T, ref_Z = martin_moyce()[2.25]
    T = t * np.sqrt(2 * 9.81 / A)
    for T_ref, Z_ref in zip(ref_T, ref_Z):
        if 1.0 <= T_ref <= 2.5:
            z = np.interp(T_ref, T, Z)
            print(f"T = {T_ref:.3f}: Z = {z:.3f} (Martin & Moyce {Z_ref:.3f}, "
                  f"{100 * (z - Z_ref) / Z_ref:+.1f} %)")
    print(f"front picture written to {out}/front.png")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "out/dam_break_c",
         float(sys.argv[2]) if len(sys.argv) > 2 else 0.01)
