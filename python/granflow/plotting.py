"""The plot scripts' common start: matplotlib with the non-interactive Agg backend (the
figures are files, made where there is no display), pyplot, and save_figure, which every
figure is written with (one resolution and cropping for all)."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)

from granflow.outputs import atomic_output  # noqa: E402

__all__ = ["plt", "save_figure"]


def save_figure(fig, path, dpi=120):
    """Save a matplotlib figure to `path` atomically."""
    out = atomic_output(path)
    try:
        fig.savefig(out.name, dpi=dpi, bbox_inches="tight")
        out.commit()
    finally:
        out.abandon()
