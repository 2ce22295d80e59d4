"""Disks drawn with their periodic images, so that a grain cut by a periodic boundary is drawn
whole on both sides (the figure clips it to the cell).

The cell is [0, lx) x [0, ly). x is periodic. When y is periodic too (simple shear), the
Lees–Edwards boundary shifts the image one period above by +δ in x, δ the frame's box edges[1][0]
(the offset the cell above has slid by), and the one below by −δ; an image one period up moves
γ̇L_y faster. Since δ can be as large as lx, images up to two periods away in x are tried."""
import numpy as np
from matplotlib.patches import Circle


def periodic_images(position, radius, lx, ly=None, offset=0.0):
    """Every image of every disk that reaches into the cell: (grain index, x, y, ky) arrays, one
    entry per image, ky the number of periods it is shifted up (0 when y is not periodic, ly =
    None). Ordered by image (ky, then kx), then by grain, so the drawing order is fixed."""
    position, radius = np.asarray(position), np.asarray(radius)
    index, xs, ys, kys = [], [], [], []
    for ky in (-1, 0, 1) if ly is not None else (0,):
        for kx in (-2, -1, 0, 1, 2):
            x = position[:, 0] + kx * lx + ky * offset
            y = position[:, 1] + ky * ly if ly is not None else position[:, 1]
            near = (x > -radius) & (x < lx + radius)
            if ly is not None:
                near &= (y > -radius) & (y < ly + radius)
            index.append(np.flatnonzero(near))
            xs.append(x[near])
            ys.append(y[near])
            kys.append(np.full(int(near.sum()), ky))
    return np.concatenate(index), np.concatenate(xs), np.concatenate(ys), np.concatenate(kys)


def circles(x, y, radius):
    """matplotlib Circle patches of the given centres and radii (for a PatchCollection)."""
    return [Circle((xi, yi), r) for xi, yi, r in zip(x, y, radius)]
