#!/usr/bin/python3
"""terratraj plots: map, profiles and convergence figures from a run's outputs.

Run by Debian's /usr/bin/python3 (python3-numpy, python3-matplotlib). `terratraj solve / plan /
refine / demo --plot OUT.png` writes a plot request (JSON) beside its outputs and runs this
script with it; it can also be run by hand on such a request:

    /usr/bin/python3 scripts/plot_results.py REQUEST.json

The request names the elevation raster (float32, row 0 = south), the map mask (uint8: 0 free,
1 lethal, 2 no data), the trajectory CSVs (the contract's columns), the iteration histories, the
reference frames, start, goal and limits, and the three PNG files to write:
  - map: hillshaded elevation, lethal cells red, no-data black, candidates thin, refined
    trajectories coloured by speed, start and goal marked, reference frames drawn;
  - profiles: speed, yaw rate, pitch and roll against time, limits dashed;
  - convergence: terminal error and cost per iteration of every solve.
"""

import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402
from matplotlib.colors import LightSource, Normalize  # noqa: E402

COLUMNS = ["t", "x", "y", "z", "heading", "roll", "pitch", "v", "omega", "curvature"]
PALETTE = ["#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd", "#8c564b", "#e377c2", "#17becf",
           "#bcbd22"]


def read_trajectory(path):
    """The trajectory CSV as a dict of column -> array (missing columns absent)."""
    with open(path, encoding="utf-8") as f:
        header = f.readline().strip().split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return {name: data[:, i] for i, name in enumerate(header) if name in COLUMNS}


def load_map(request):
    m = request["map"]
    rows, cols, cell = m["rows"], m["cols"], m["cell"]
    z = np.fromfile(m["elevation"], dtype="<f4").reshape(rows, cols)
    mask = np.fromfile(m["mask"], dtype="u1").reshape(rows, cols)
    return z, mask, cell


def draw_map(request, trajectories, out):
    z, mask, cell = load_map(request)
    rows, cols = z.shape
    extent = [0.0, cols * cell, 0.0, rows * cell]
    fig, ax = plt.subplots(figsize=(9, 9), dpi=110)
    filled = np.where(np.isfinite(z), z, np.nanmin(z) if np.isfinite(z).any() else 0.0)
    light = LightSource(azdeg=315, altdeg=45)
    # LightSource expects row 0 at the top; our rows start in the south: flip for shading only.
    # The colour scale starts below the lowest height: gist_earth's bottom is black, which is
    # the colour of no-data cells here.
    low, high = float(np.min(filled)), float(np.max(filled))
    vmin = low - 0.2 * max(high - low, 1e-6)
    shaded = light.shade(filled[::-1], cmap=plt.cm.gist_earth, vert_exag=1.0, blend_mode="soft",
                         dx=cell, dy=cell, vmin=vmin, vmax=high)[::-1]
    ax.imshow(shaded, origin="lower", extent=extent, interpolation="bilinear")
    elevation = ax.imshow(filled, origin="lower", extent=extent, cmap=plt.cm.gist_earth, alpha=0.0,
                          vmin=vmin, vmax=high)
    overlay = np.zeros((rows, cols, 4))
    overlay[mask == 1] = [0.85, 0.05, 0.05, 0.85]
    overlay[mask == 2] = [0.0, 0.0, 0.0, 1.0]
    ax.imshow(overlay, origin="lower", extent=extent, interpolation="nearest")

    for k, frame in enumerate(request.get("frames", [])):
        (x0, y0), (x1, y1) = frame["start"], frame["end"]
        ax.plot([x0, x1], [y0, y1], color="magenta", lw=1.4, ls="--",
                label="reference frames" if k == 0 else None)
        ax.annotate(frame["name"], ((x0 + x1) / 2, (y0 + y1) / 2), color="magenta",
                    fontsize=10, fontweight="bold", ha="center", va="bottom")

    speeds = [t["data"]["v"] for t in trajectories if t["role"] != "candidate" and "v" in t["data"]]
    v_max = request.get("limits", {}).get("v_max")
    vmax = v_max if v_max else (max(float(np.max(s)) for s in speeds) if speeds else 1.0)
    norm = Normalize(vmin=0.0, vmax=vmax)
    line_collection = None
    for t in trajectories:
        d = t["data"]
        colour = PALETTE[t["group"] % len(PALETTE)]
        if t["role"] == "candidate":
            ax.plot(d["x"], d["y"], color=colour, lw=1.0, ls=(0, (4, 2)), alpha=0.95,
                    label=t["label"])
            continue
        points = np.column_stack([d["x"], d["y"]]).reshape(-1, 1, 2)
        segments = np.concatenate([points[:-1], points[1:]], axis=1)
        # A dark casing under the speed colours so the line reads on any terrain.
        ax.plot(d["x"], d["y"], color="black", lw=4.6, alpha=0.55, solid_capstyle="round")
        line_collection = LineCollection(segments, cmap=plt.cm.plasma, norm=norm, linewidths=3.0)
        line_collection.set_array(0.5 * (d["v"][:-1] + d["v"][1:]) if "v" in d else
                                  np.zeros(len(segments)))
        ax.add_collection(line_collection)
        # Labels spread along the routes so that overlapping routes keep readable labels.
        at = int((0.2 + 0.25 * (t["group"] % 3)) * (len(d["x"]) - 1))
        ax.annotate(t["label"], (d["x"][at], d["y"][at]), xytext=(6, 10 - 24 * (t["group"] % 2)),
                    textcoords="offset points", fontsize=8, color="white",
                    bbox=dict(boxstyle="round,pad=0.2", fc=colour, alpha=0.85, lw=0))

    for key, marker, colour, name in (("start", "o", "#00c853", "start"),
                                      ("goal", "*", "#ffd600", "goal")):
        pose = request.get(key)
        if not pose:
            continue
        ax.plot(pose["x"], pose["y"], marker=marker, ms=15 if marker == "*" else 11, color=colour,
                mec="black", mew=1.2, ls="none", label=name, zorder=5)
        length = 0.03 * max(extent[1], extent[3])
        ax.arrow(pose["x"], pose["y"], length * np.cos(pose["heading"]),
                 length * np.sin(pose["heading"]), color="black", width=0.004 * extent[1],
                 zorder=6, length_includes_head=True)

    cbar_z = fig.colorbar(elevation, ax=ax, fraction=0.035, pad=0.01)
    cbar_z.set_label("elevation [m]")
    cbar_z.solids.set(alpha=1.0)
    if line_collection is not None:
        cbar_v = fig.colorbar(plt.cm.ScalarMappable(norm=norm, cmap=plt.cm.plasma), ax=ax,
                              orientation="horizontal", fraction=0.035, pad=0.08, aspect=40)
        cbar_v.set_label("speed of refined trajectories [m/s]")
    handles, labels = ax.get_legend_handles_labels()
    if (mask == 1).any():
        handles.append(plt.Rectangle((0, 0), 1, 1, fc=(0.85, 0.05, 0.05)))
        labels.append("lethal")
    if (mask == 2).any():
        handles.append(plt.Rectangle((0, 0), 1, 1, fc="black"))
        labels.append("no data")
    ax.legend(handles, labels, loc="upper left", fontsize=8, framealpha=0.85)
    ax.set_xlim(extent[0], extent[1])
    ax.set_ylim(extent[2], extent[3])
    ax.set_aspect("equal")
    ax.set_xlabel("x (east) [m]")
    ax.set_ylabel("y (north) [m]")
    ax.set_title(request.get("title", "terratraj"))
    fig.tight_layout()
    fig.savefig(out)
    plt.close(fig)


def draw_profiles(request, trajectories, out):
    limits = request.get("limits", {})
    panels = [("v", "speed [m/s]", [limits.get("v_max")], 1.0),
              ("omega", "yaw rate [rad/s]", [limits.get("omega_max")], 1.0),
              ("pitch", "pitch [deg]", [limits.get("pitch_max")], 180.0 / np.pi),
              ("roll", "roll [deg]", [limits.get("roll_max")], 180.0 / np.pi)]
    fig, axes = plt.subplots(len(panels), 1, figsize=(9, 9), dpi=110, sharex=True)
    for ax, (column, label, bounds, scale) in zip(axes, panels):
        for t in trajectories:
            d = t["data"]
            if column not in d or "t" not in d:
                continue
            colour = PALETTE[t["group"] % len(PALETTE)]
            candidate = t["role"] == "candidate"
            ax.plot(d["t"], d[column] * scale, color=colour, lw=0.9 if candidate else 2.0,
                    ls=":" if candidate else "-", label=t["label"])
        for bound in bounds:
            if bound is None:
                continue
            ax.axhline(bound * scale, color="crimson", ls="--", lw=1.2)
            if column != "v":
                ax.axhline(-bound * scale, color="crimson", ls="--", lw=1.2)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[0].plot([], [], color="crimson", ls="--", label="limits")
    axes[0].legend(fontsize=8, ncol=2, loc="lower center")
    axes[-1].set_xlabel("time [s]")
    axes[0].set_title((request.get("title", "") + ": profiles").strip(": "))
    fig.tight_layout()
    fig.savefig(out)
    plt.close(fig)


def draw_convergence(request, out):
    histories = [h for h in request.get("histories", []) if h["iterations"]]
    fig, (ax_error, ax_cost) = plt.subplots(2, 1, figsize=(9, 6.5), dpi=110, sharex=True)
    for k, h in enumerate(histories):
        it = [r["iteration"] for r in h["iterations"]]
        err = [r["terminal_error"] if r["terminal_error"] is not None else np.nan
               for r in h["iterations"]]
        cost = [r["cost"] if r["cost"] is not None else np.nan for r in h["iterations"]]
        colour = PALETTE[h.get("group", k) % len(PALETTE)]
        ax_error.semilogy(it, np.maximum(np.array(err, dtype=float), 1e-16), marker=".",
                          color=colour, label=h["label"])
        ax_cost.plot(it, cost, marker=".", color=colour, label=h["label"])
    tolerance = request.get("tolerance_position_m")
    if tolerance:
        ax_error.axhline(tolerance, color="crimson", ls="--", lw=1.2, label="tolerance")
    ax_error.set_ylabel("terminal error [m]\n(transcription: max defect)")
    ax_cost.set_ylabel("cost [s]")
    ax_cost.set_xlabel("iteration")
    for ax in (ax_error, ax_cost):
        ax.grid(alpha=0.3, which="both")
    if histories:
        ax_error.legend(fontsize=8)
    else:
        ax_error.text(0.5, 0.5, "no iterations recorded", transform=ax_error.transAxes,
                      ha="center")
    ax_error.set_title((request.get("title", "") + ": convergence").strip(": "))
    fig.tight_layout()
    fig.savefig(out)
    plt.close(fig)


def main(argv):
    if len(argv) != 2:
        print("usage: plot_results.py REQUEST.json", file=sys.stderr)
        return 2
    with open(argv[1], encoding="utf-8") as f:
        request = json.load(f)
    trajectories = []
    for t in request.get("trajectories", []):
        data = read_trajectory(t["csv"])
        if "x" not in data or "y" not in data or len(data["x"]) < 2:
            continue
        trajectories.append(dict(t, data=data))
    outputs = request["outputs"]
    draw_map(request, trajectories, outputs["map"])
    draw_profiles(request, trajectories, outputs["profiles"])
    draw_convergence(request, outputs["convergence"])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
