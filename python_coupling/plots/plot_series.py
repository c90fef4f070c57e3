#!/usr/bin/python3
"""Plot the time series of a polydem run (RUN_DIR/series.csv) to a PNG.

By default related columns share a panel (a monitored block's x, y, z; its vx, vy, vz; the
rotations of all monitored blocks; kinetic energy with the force ratio on a second axis); columns
chosen with --columns get a panel each. When a column `<name>_analytic` sits beside
`<name>`, the panel shows both (numerical solid, analytical dashed) and the relative error
|numerical - analytical| / |analytical| on a second axis. Units come from summary.json's
"series_units" map when the run wrote one, otherwise from the column name (see UNITS below).
The title names the scene and the verdict of its checks when RUN_DIR/summary.json exists.

Runs with Debian's /usr/bin/python3 (matplotlib, numpy), headless (Agg backend):

    /usr/bin/python3 python_coupling/plots/plot_series.py RUN_DIR [--columns a,b] [--out f.png]

The same functions are the module polydem.plots of the Python package (read_series, plot, ...);
as functions they raise ValueError where the script exits with a message.
"""
import argparse
import csv
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)
import numpy as np  # noqa: E402

ANALYTIC = "_analytic"
MAX_DEFAULT_PANELS = 12

# Unit of a column from its full name, then from the end of its name (longest match first).
UNITS_BY_NAME = {
    "time": "s", "step": "-", "dt": "s", "kinetic_energy": "J", "potential_energy": "J",
    "energy": "J", "force_ratio": "-", "contacts": "count", "wall_time": "s",
}
UNITS_BY_SUFFIX = [
    ("_angle_deg", "deg"), ("_deg", "deg"), ("_rotation", "rad"), ("_angle", "rad"),
    ("_vx", "m/s"), ("_vy", "m/s"), ("_vz", "m/s"), ("_speed", "m/s"), ("_velocity", "m/s"),
    ("_wx", "rad/s"), ("_wy", "rad/s"), ("_wz", "rad/s"),
    ("_x", "m"), ("_y", "m"), ("_z", "m"), ("_displacement", "m"), ("_drift", "m"),
    ("_runout", "m"), ("_depth", "m"), ("_energy", "J"), ("_force", "N"), ("_ratio", "-"),
]


def unit_of(name, units):
    if name in units:
        return units[name]
    if name in UNITS_BY_NAME:
        return UNITS_BY_NAME[name]
    for suffix, unit in UNITS_BY_SUFFIX:
        if name.endswith(suffix):
            return unit
    return None


def label_of(name, units):
    unit = unit_of(name, units)
    text = name.replace("_", " ")
    return "%s [%s]" % (text, unit) if unit else text


def read_series(path):
    """The columns of a series.csv: (header, {name: numpy array}); a torn last row is skipped."""
    with open(path, newline="") as f:
        reader = csv.reader(f)
        try:
            header = next(reader)
        except StopIteration:
            raise ValueError("%s is empty" % path) from None
        rows = [r for r in reader if len(r) == len(header)]  # a torn last row is skipped
    data = np.array([[float(v) for v in r] for r in rows], dtype=float).reshape(-1, len(header))
    return header, {name: data[:, i] for i, name in enumerate(header)}


def read_summary(run_dir):
    path = os.path.join(run_dir, "summary.json")
    if not os.path.exists(path):
        return {}
    try:
        with open(path) as f:
            summary = json.load(f)
        return summary if isinstance(summary, dict) else {}
    except (OSError, ValueError) as e:
        print("plot_series: ignoring %s: %s" % (path, e), file=sys.stderr)
        return {}


def title_of(summary, run_dir):
    name = " - ".join(str(summary[k]) for k in ("id", "title") if summary.get(k))
    lines = [name or os.path.basename(os.path.abspath(run_dir))]
    checks = summary.get("checks")
    if isinstance(checks, list) and checks:
        failed = [str(c.get("name", "?")) for c in checks if isinstance(c, dict)
                  and c.get("pass") is False]
        verdict = "checks: %d of %d pass" % (len(checks) - len(failed), len(checks))
        if failed:
            verdict += " (failed: %s)" % ", ".join(failed)
        lines.append(verdict)
    return "\n".join(lines)


def relative_error(numerical, analytical):
    with np.errstate(divide="ignore", invalid="ignore"):
        error = np.abs(numerical - analytical) / np.abs(analytical)
    error[~np.isfinite(error)] = np.nan  # undefined where the analytical value is zero
    return error


def plot_panel(ax, x, name, series, units):
    if name + ANALYTIC not in series:
        ax.plot(x, series[name], color="C0", lw=1.6, label=name.replace("_", " "))
        ax.set_ylabel(label_of(name, units))
        return [ax]
    analytic = series[name + ANALYTIC]
    ax.plot(x, series[name], color="C0", lw=1.8, label="numerical")
    ax.plot(x, analytic, color="k", lw=1.2, ls="--", label="analytical")
    ax.set_ylabel(label_of(name, units))
    err_ax = ax.twinx()
    error = relative_error(series[name], analytic)
    err_ax.plot(x, error, color="C3", lw=0.9, ls=":", label="relative error")
    positive = error[np.isfinite(error) & (error > 0)]
    if positive.size and positive.max() / positive.min() > 100:
        err_ax.set_yscale("log")  # errors over decades (e.g. growing from round-off)
    elif positive.size:
        # From zero, so that a small constant error does not look like noise around an offset.
        err_ax.set_ylim(0.0, 1.15 * positive.max())
        err_ax.ticklabel_format(axis="y", style="sci", scilimits=(-2, 3), useOffset=False)
    err_ax.set_ylabel("relative error [-]", color="C3")
    err_ax.tick_params(axis="y", colors="C3")
    finite = error[np.isfinite(error)]
    if finite.size:
        ax.set_title("max relative error %.3g" % finite.max(), fontsize=9, loc="right")
    return [ax, err_ax]


def group_panels(columns):
    """Panels of related columns, in the order of their first column: a block's x, y, z in one
    panel and its vx, vy, vz in another, the rotations of all monitored blocks together, kinetic
    energy with the force ratio (on a second axis); every other column alone. A column with an
    analytical partner stays alone (its panel shows the error)."""
    keys = []
    panels = {}
    for name in columns:
        key = (name,)
        alone = name + ANALYTIC in columns
        for suffixes, kind in ((("_x", "_y", "_z"), "position"), (("_vx", "_vy", "_vz"), "velocity")):
            for suffix in suffixes:
                prefix = name[:-len(suffix)]
                if name.endswith(suffix) and not alone and all(
                        prefix + s in columns and prefix + s + ANALYTIC not in columns
                        for s in suffixes):
                    key = (prefix, kind)
        if name.endswith("_rotation") and not alone:
            key = ("rotation",)
        if name in ("kinetic_energy", "force_ratio") and not alone:
            key = ("energy",)
        if key not in panels:
            keys.append(key)
            panels[key] = []
        panels[key].append(name)
    return [panels[k] for k in keys]


def plot_group(ax, x, names, series, units):
    """Several columns in one panel: one axis when they share a unit, else a second axis for the
    second unit (kinetic energy and force ratio)."""
    unit = unit_of(names[0], units)
    first = [n for n in names if unit_of(n, units) == unit]
    second = [n for n in names if unit_of(n, units) != unit]
    # A block's x, y, z (or vx, vy, vz): the block's label once, the component in the legend.
    prefix, what = "", ""
    for suffix, kind in (("_vx", "velocity"), ("_x", "position")):
        if len(first) > 1 and first[0].endswith(suffix):
            prefix, what = first[0][:-len(suffix)], kind
    for i, name in enumerate(first):
        legend = name[len(prefix) + 1:] if prefix else name.replace("_", " ")
        ax.plot(x, series[name], color="C%d" % i, lw=1.5, label=legend)
    if prefix:
        ax.set_ylabel("%s %s [%s]" % (prefix.replace("_", " "), what, unit))
    elif len(first) > 1:
        ax.set_ylabel("%s [%s]" % (first[0].split("_")[-1], unit))
    else:
        ax.set_ylabel(label_of(first[0], units))
    drawn = [ax]
    if second:
        twin = ax.twinx()
        for i, name in enumerate(second):
            twin.plot(x, series[name], color="C%d" % (len(first) + i), lw=1.2, ls="--",
                      label=name.replace("_", " "))
        twin.set_ylabel(label_of(second[0], units))
        values = np.concatenate([series[n] for n in second])
        positive = values[values > 0]
        if positive.size and positive.max() / positive.min() > 1000:
            twin.set_yscale("log")  # a force ratio falls over decades as a deposit settles
        drawn.append(twin)
    return drawn


def choose_columns(header, x_name, requested):
    """The columns to plot: `requested` (a list, or names separated by commas) or all of them."""
    if requested:
        if isinstance(requested, str):
            requested = requested.split(",")
        chosen = [c.strip() for c in requested if c.strip()]
        missing = [c for c in chosen if c not in header]
        if missing:
            raise ValueError("no column %s in series.csv (columns: %s)"
                             % (", ".join(missing), ", ".join(header)))
        return chosen
    chosen = [c for c in header if c not in (x_name, "step") and not c.endswith(ANALYTIC)]
    if len(chosen) > MAX_DEFAULT_PANELS:
        print("plot_series: plotting the first %d of %d columns; choose with --columns"
              % (MAX_DEFAULT_PANELS, len(chosen)), file=sys.stderr)
        chosen = chosen[:MAX_DEFAULT_PANELS]
    return chosen


def plot(run_dir, columns=None, out=None, x="time"):
    """Draws columns of RUN_DIR/series.csv against `x`, one panel each, to a PNG.

    `columns`: a list of names (or one string of names separated by commas); default all but
    `x`, step and the *_analytic columns, which are drawn beside their numerical column. `out`:
    the PNG (default RUN_DIR/series.png). Returns the path written. Raises ValueError for a column
    that is not in the file.
    """
    header, series = read_series(os.path.join(run_dir, "series.csv"))
    if x not in series:
        raise ValueError("no column %s in series.csv" % x)
    summary = read_summary(run_dir)
    units = summary.get("series_units") if isinstance(summary.get("series_units"), dict) else {}
    if columns is None:
        # By default related columns share a panel (at most MAX_DEFAULT_PANELS panels).
        columns = [c for c in header if c not in (x, "step") and not c.endswith(ANALYTIC)]
        panels = group_panels(columns + [c for c in header if c.endswith(ANALYTIC)])
        panels = [[c for c in p if not c.endswith(ANALYTIC)] for p in panels]
        panels = [p for p in panels if p]
        if len(panels) > MAX_DEFAULT_PANELS:
            print("plot_series: plotting the first %d of %d panels; choose with --columns"
                  % (MAX_DEFAULT_PANELS, len(panels)), file=sys.stderr)
            panels = panels[:MAX_DEFAULT_PANELS]
    else:
        panels = [[c] for c in choose_columns(header, x, columns)]  # chosen: a panel each
    if not panels:
        raise ValueError("nothing to plot besides %s" % x)

    n = len(panels)
    ncols = 1 if n <= 3 else 2
    nrows = math.ceil(n / ncols)
    fig, axes = plt.subplots(nrows, ncols, sharex=True, squeeze=False,
                             figsize=(7.5 * ncols, 2.8 * nrows + 0.9))
    xs = series[x]
    for i, names in enumerate(panels):
        ax = axes[i // ncols][i % ncols]
        if len(names) == 1:
            drawn = plot_panel(ax, xs, names[0], series, units)
        else:
            drawn = plot_group(ax, xs, names, series, units)
        ax.grid(True, which="major", alpha=0.35)
        ax.grid(True, which="minor", alpha=0.12)
        ax.minorticks_on()
        handles = [h for a in drawn for h in a.get_legend_handles_labels()[0]]
        labels = [lb for a in drawn for lb in a.get_legend_handles_labels()[1]]
        ax.legend(handles, labels, fontsize=8, loc="best", framealpha=0.85)
    for j in range(n, nrows * ncols):
        axes[j // ncols][j % ncols].set_visible(False)
    for col in range(ncols):
        last = max(i for i in range(n) if i % ncols == col) if n > col else None
        if last is not None:
            axes[last // ncols][col].set_xlabel(label_of(x, units))
            axes[last // ncols][col].tick_params(labelbottom=True)
    fig.suptitle(title_of(summary, run_dir), fontsize=11)
    fig.tight_layout()
    out = out or os.path.join(run_dir, "series.png")
    fig.savefig(out, dpi=150)
    plt.close(fig)
    return out


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("run_dir", help="directory of a run (holds series.csv)")
    parser.add_argument("--columns", help="comma-separated columns to plot (default: all)")
    parser.add_argument("--out", help="PNG to write (default: RUN_DIR/series.png)")
    parser.add_argument("--x", default="time", help="column on the horizontal axis")
    args = parser.parse_args(argv)
    try:
        out = plot(args.run_dir, args.columns, args.out, args.x)
    except ValueError as e:
        sys.exit("plot_series: %s" % e)
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
