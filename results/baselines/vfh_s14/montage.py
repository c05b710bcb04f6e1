"""Tile episode pictures (`nav-bench episode ... --plot`) into one PNG, cropped to the map.
python results/baselines/vfh_s14/montage.py OUT.png COLUMNS IN.png [IN.png ...]
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg
import matplotlib.pyplot as plt

out, cols, paths = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
rows = -(-len(paths) // cols)
fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.6 * rows), squeeze=False)
for ax in axes.ravel():
    ax.axis("off")
for ax, path in zip(axes.ravel(), paths, strict=False):
    img = mpimg.imread(path)
    h = img.shape[0]
    ax.imshow(img[: int(h * 0.86)])  # the map and its title, without the legend
fig.tight_layout(pad=0.2)
fig.savefig(out, dpi=80)
