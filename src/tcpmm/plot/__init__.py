"""Plots for reports. The only place matplotlib is imported, and only when a plot is made."""

from __future__ import annotations

from pathlib import Path

SENSOR_STYLE = {
    "cmd": dict(color="black", ls="--", lw=1.0, label="Reference"),
    "motor": dict(color="tab:green", ls="-", lw=1.0, label="ENC (motor encoder)"),
    "scale": dict(color="tab:red", ls=":", lw=1.4, label="LS (linear scale)"),
    "tcp": dict(color="tab:blue", ls="-", lw=1.2, label="TCP"),
}


def pyplot():
    """matplotlib.pyplot with a non-interactive backend."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    return plt


def plot_file(path) -> Path:
    """Check that ``path`` names a file format matplotlib writes; return it as a Path.

    Parameters
    ----------
    path : str or Path
        Plot file [-].
    """
    from matplotlib.backend_bases import FigureCanvasBase

    from ..errors import InputError

    path = Path(path)
    kinds = FigureCanvasBase.get_supported_filetypes()
    if path.suffix.lower().lstrip(".") not in kinds:
        raise InputError(f"a plot file needs one of the extensions {', '.join(sorted(kinds))} "
                         "(e.g. .png, .pdf or .svg)", file=path)
    return path


def save(fig, path) -> Path | None:
    """Save a figure atomically and close it; return the path (None: figure kept open)."""
    if path is None:
        return None
    from ..io.atomic import atomic_path

    try:
        path = plot_file(path)
    except Exception:
        pyplot().close(fig)
        raise
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=130, bbox_inches="tight")
    pyplot().close(fig)
    return path
