import sys, glob, os
import numpy as np, matplotlib
matplotlib.use('Agg'); import matplotlib.pyplot as plt
d = sys.argv[1]; files = sorted(glob.glob(d + '/snap_*.csv'))
n = len(files); cols = min(4, n); rows = (n + cols - 1) // cols
fig, axs = plt.subplots(rows, cols, figsize=(4 * cols, 4.2 * rows), squeeze=False)
for ax, f in zip(axs.flat, files):
    a = np.genfromtxt(f, delimiter=',', names=True)
    w = (a['kind'] == 0) & (a['fluid'] == 0); g = (a['kind'] == 0) & (a['fluid'] == 1); s = (a['kind'] == 1) | (a['kind'] == 2)  # walls, dummies; not kind 3, fluid out of the run
    ax.scatter(a['x'][s], a['y'][s], s=1, c='k')
    ax.scatter(a['x'][g], a['y'][g], s=2, c='orange')
    ax.scatter(a['x'][w], a['y'][w], s=3, c='b')
    ax.set_aspect('equal'); ax.set_xlim(-0.04, 0.64); ax.set_ylim(-0.04, 0.8)
    ax.set_title(os.path.basename(f)[5:-4] + ' s')
plt.tight_layout(); plt.savefig(d + '/snaps.png', dpi=70)
