#!/usr/bin/env python3
"""Publication plots of an airring run folder with matplotlib (PDF + PNG, 300 dpi).

    plot_run.py RUN_DIR [--out DIR] [--formats pdf,png]

Reads RUN_DIR/timeseries.csv (and summary.json for the clearance, class and onset) and writes:
  eps.{pdf,png}        eccentricities eps_C, eps_T vs time, with the rotor speed on a second axis
  journal_y.{pdf,png}  vertical journal positions y_JC, y_JT [um]
  orbits.{pdf,png}     journal orbits relative to the rings (dx, dy) in both bearings [um]
  forces.{pdf,png}     film forces Fx, Fy of both bearings
(figures whose variables were not recorded are skipped). Uses the Agg backend: no display needed.
"""
from __future__ import annotations

import argparse
import json
import math
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

plt.rcParams.update({"font.size": 9, "axes.grid": True, "grid.alpha": 0.3, "figure.dpi": 100,
                     "savefig.dpi": 300, "lines.linewidth": 0.9, "figure.figsize": (6.3, 3.4)})


def load(run: pathlib.Path) -> dict[str, np.ndarray]:
    path = run / "timeseries.csv"
    header = path.read_text().split("\n", 1)[0].split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return {h.split(" [")[0]: data[:, i] for i, h in enumerate(header)}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("run")
    ap.add_argument("--out", help="output folder (default: RUN/plots)")
    ap.add_argument("--formats", default="pdf,png")
    a = ap.parse_args(argv)
    run = pathlib.Path(a.run)
    out = pathlib.Path(a.out) if a.out else run / "plots"
    out.mkdir(parents=True, exist_ok=True)
    d = load(run)
    try:
        summary = json.loads((run / "summary.json").read_text())
    except (OSError, ValueError):
        summary = {}
    settings = summary.get("settings") or {}
    clearance = (settings.get("clearance_um") or 20.0) * 1e-6
    onset = summary.get("onset_time_s")
    label = summary.get("classification")
    t_ms = d["time"] * 1e3
    written = []

    def save(fig, stem):
        fig.tight_layout()
        for fmt in a.formats.split(","):
            p = out / f"{stem}.{fmt.strip()}"
            fig.savefig(p)
            written.append(p)
        plt.close(fig)

    def mark_onset(ax):
        if onset is not None:
            ax.axvline(onset * 1e3, color="k", ls="--", lw=0.8)
            ax.text(onset * 1e3, ax.get_ylim()[1], f" onset ({label})", va="top", fontsize=8)

    has = lambda *names: all(n in d for n in names)  # noqa: E731
    if has("rotor.dx_C", "rotor.dy_C", "rotor.dx_T", "rotor.dy_T"):
        fig, ax = plt.subplots()
        for b, c in (("C", "tab:blue"), ("T", "tab:red")):
            ax.plot(t_ms, np.hypot(d[f"rotor.dx_{b}"], d[f"rotor.dy_{b}"]) / clearance, color=c, label=f"$\\varepsilon_{b}$")
        ax.set_xlabel("t [ms]")
        ax.set_ylabel(r"$\varepsilon = |\Delta r| / C$ [-]")
        if "rotor.omega" in d:
            ax2 = ax.twinx()
            ax2.plot(t_ms, d["rotor.omega"] / (2 * math.pi), color="0.5", lw=0.7, label="speed")
            ax2.set_ylabel("speed [Hz]")
            ax2.grid(False)
        ax.legend(loc="upper left")
        mark_onset(ax)
        save(fig, "eps")

        fig, axs = plt.subplots(1, 2, figsize=(6.3, 3.2))
        for ax, b in zip(axs, ("C", "T")):
            ax.plot(d[f"rotor.dx_{b}"] * 1e6, d[f"rotor.dy_{b}"] * 1e6, lw=0.5)
            circle = np.linspace(0, 2 * math.pi, 200)
            ax.plot(clearance * 1e6 * np.cos(circle), clearance * 1e6 * np.sin(circle), "k:", lw=0.6)
            ax.set_aspect("equal")
            ax.set_title(f"bearing {b}")
            ax.set_xlabel(r"$\Delta x$ [um]")
            ax.set_ylabel(r"$\Delta y$ [um]")
        save(fig, "orbits")
    if has("rotor.y_JC", "rotor.y_JT"):
        fig, ax = plt.subplots()
        ax.plot(t_ms, d["rotor.y_JC"] * 1e6, label="$y_{JC}$")
        ax.plot(t_ms, d["rotor.y_JT"] * 1e6, label="$y_{JT}$")
        ax.set_xlabel("t [ms]")
        ax.set_ylabel("y [um]")
        ax.legend()
        mark_onset(ax)
        save(fig, "journal_y")
    if has("film_C.Fx", "film_C.Fy", "film_T.Fx", "film_T.Fy"):
        fig, ax = plt.subplots()
        for n in ("film_C.Fx", "film_C.Fy", "film_T.Fx", "film_T.Fy"):
            ax.plot(t_ms, d[n], label=n)
        ax.set_xlabel("t [ms]")
        ax.set_ylabel("F [N]")
        ax.legend(ncol=2)
        save(fig, "forces")
    print(f"{len(written)} files -> {out}", file=sys.stderr)
    return 0 if written else 1


if __name__ == "__main__":
    sys.exit(main())
