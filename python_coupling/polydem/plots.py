"""Plots of a run's time series (series.csv), with matplotlib's Agg backend (no display needed).

The functions of python_coupling/plots/plot_series.py, which is also a script of its own:

    import polydem
    header, series = polydem.plots.read_series("out/series.csv")   # dict of numpy columns
    polydem.plots.plot("out", columns=["cube_z"], out="cube.png")   # -> path of the PNG

Importing this module imports matplotlib (and selects the Agg backend).
"""
from ._plot_series import (
    choose_columns,
    label_of,
    plot,
    read_series,
    read_summary,
    relative_error,
    unit_of,
)

__all__ = ["choose_columns", "label_of", "plot", "read_series", "read_summary",
           "relative_error", "unit_of"]
