#!/usr/bin/python3
"""Figures of a `terratraj bench` result file (embedded in the executable; run by
`terratraj bench ... --plot FILE.png` with Debian's python3 and matplotlib).

Usage: plot_bench.py REQUEST.json, where the request holds {"result": the result file,
"png": the figure to write, "files": where to list the files written (JSON)}.
"""
import json
import os
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

SOLVERS = ["newton_fd", "newton", "ipopt", "ceres", "shooting", "collocation",
           "collocation_refined"]


def profile(ax, rows, measure, title):
    """Dolan-More performance profile: fraction of problems a solver solves within tau times
    the best solver's measure (failures never)."""
    problems = {}
    for r in rows:
        key = (r["set"], r["problem"])
        ok = r.get("status") == "converged" and isinstance(r.get(measure), (int, float))
        # Counts start at 1 (a solver that converged at its initial guess used 0 iterations).
        value = max(r[measure], 1) if ok and measure == "iterations" else r.get(measure)
        problems.setdefault(key, {})[r["solver"]] = value if ok else math.inf
    taus = [2 ** (k / 8.0) for k in range(0, 8 * 12 + 1)]
    for solver in SOLVERS:
        ratios = []
        for per in problems.values():
            finite = [v for v in per.values() if v < math.inf]
            best = max(min(finite), 1e-9) if finite else math.inf
            value = per.get(solver, math.inf)
            ratios.append(value / best if value < math.inf else math.inf)
        if not ratios:
            continue
        rho = [sum(1 for x in ratios if x <= t) / len(ratios) for t in taus]
        ax.step(taus, rho, where="post", label=solver)
    ax.set_xscale("log", base=2)
    ax.set_ylim(0, 1.02)
    ax.set_xlabel("tau (ratio to the best solver)")
    ax.set_ylabel("fraction of problems")
    ax.set_title(title)
    ax.grid(True, alpha=0.3)


ROBUST_METHODS = ["auto", "newton", "ipopt", "ceres", "collocation"]


def robustness(result, png):
    """Success per method and set, and the cost over the Dubins bound (constant-speed turns)."""
    rows = [r for r in result["rows"] if r.get("family") == "robustness"
            and r.get("status") != "skipped"]
    fig, axes = plt.subplots(1, 2, figsize=(14, 5))
    methods = [m for m in ROBUST_METHODS if any(r["solver"] == m for r in rows)]
    rates = []
    for m in methods:
        mine = [r for r in rows if r["solver"] == m]
        rates.append(sum(1 for r in mine if r.get("status") == "converged") / max(len(mine), 1))
    axes[0].bar(methods, rates)
    axes[0].axhline(0.99, color="k", ls="--", lw=0.8, label="99 % (default method)")
    axes[0].axhline(0.95, color="gray", ls=":", lw=0.8, label="95 %")
    axes[0].set_ylim(0, 1.02)
    axes[0].set_ylabel("converged and verified")
    axes[0].set_title("success on the robustness set")
    axes[0].legend(loc="lower right")
    data, labels = [], []
    for m in methods:
        values = [r["cost_over_bound"] for r in rows
                  if r["solver"] == m and r.get("status") == "converged"
                  and isinstance(r.get("cost_over_bound"), (int, float))]
        if values:
            data.append(values)
            labels.append(m)
    if data:
        axes[1].boxplot(data, labels=labels, whis=(0, 100))
    axes[1].axhline(1.02, color="k", ls="--", lw=0.8)
    axes[1].axhline(1.10, color="gray", ls=":", lw=0.8)
    axes[1].set_ylabel("time / Dubins length at v (converged)")
    axes[1].set_title("constant-speed turns: cost over the Dubins bound")
    fig.suptitle(title(result))
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    return [png]


def convergence(result, png):
    rows = [r for r in result["rows"] if r.get("family") != "robustness"]
    files = []
    if len(rows) != len(result["rows"]):
        stem, ext = os.path.splitext(png)
        files = robustness(result, stem + "-robustness" + (ext or ".png"))
    fig, axes = plt.subplots(1, 3, figsize=(17, 5))
    profile(axes[0], rows, "time_ms", "performance profile: time")
    profile(axes[1], rows, "iterations", "performance profile: iterations")
    best = {}
    for r in rows:
        if r.get("status") == "converged" and isinstance(r.get("cost"), (int, float)):
            key = (r["set"], r["problem"], r.get("formulation"))
            best[key] = min(best.get(key, math.inf), r["cost"])
    data, labels = [], []
    for solver in SOLVERS:
        values = [r["cost"] / best[(r["set"], r["problem"], r.get("formulation"))] - 1.0
                  for r in rows
                  if r["solver"] == solver and r.get("status") == "converged"
                  and isinstance(r.get("cost"), (int, float))]
        if values:
            data.append([max(v, 1e-7) for v in values])
            labels.append(solver)
    if data:
        axes[2].boxplot(data, labels=labels, whis=(0, 100))
        axes[2].set_yscale("log")
    axes[2].set_ylabel("cost / best cost - 1 (converged; floor 1e-7)")
    axes[2].set_title("cost relative to the best solver of its formulation")
    axes[2].tick_params(axis="x", rotation=30)
    axes[0].legend(loc="lower right")
    fig.suptitle(title(result))
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    return [png] + files


def planners(result, png):
    rows = [r for r in result["rows"] if "prm" in r]
    fig, axes = plt.subplots(1, 3, figsize=(17, 5))
    env = [r for r in rows if r["experiment"] == "environment"]
    kinds = sorted({r["kind"] for r in env})
    for kind in kinds:
        sizes = sorted({r["size"] for r in env if r["kind"] == kind})
        first, ara = [], []
        for s in sizes:
            v = [r["prm"]["first_ms"] for r in env if r["kind"] == kind and r["size"] == s
                 and r["prm"]["first_ms"] is not None]
            a = [r["lattice"]["ara"]["first_ms"] for r in env if r["kind"] == kind
                 and r["size"] == s and r.get("lattice", {}).get("ara", {}).get("first_ms")]
            first.append(sorted(v)[len(v) // 2] if v else math.nan)
            ara.append(sorted(a)[len(a) // 2] if a else math.nan)
        line = axes[0].plot(sizes, first, "o-", label=kind + " PRM")[0]
        axes[0].plot(sizes, ara, "s--", color=line.get_color(), label=kind + " ARA*")
        costs_1s, costs_final = [], []
        for s in sizes:
            c1 = [r["prm"]["cost_1s"] / r["lower_bound_s"] for r in env
                  if r["kind"] == kind and r["size"] == s and r["prm"]["cost_1s"] is not None]
            cf = [r["prm"]["cost_final_s"] / r["lower_bound_s"] for r in env
                  if r["kind"] == kind and r["size"] == s and r["prm"]["cost_final_s"] is not None]
            costs_1s.append(sorted(c1)[len(c1) // 2] if c1 else math.nan)
            costs_final.append(sorted(cf)[len(cf) // 2] if cf else math.nan)
        axes[1].plot(sizes, costs_1s, "o-", color=line.get_color(), label=kind + " at 1 s")
        axes[1].plot(sizes, costs_final, "s:", color=line.get_color(), label=kind + " at budget")
    axes[0].set_xscale("log", base=2)
    axes[0].set_yscale("log")
    axes[0].set_xlabel("map size (cells per side)")
    axes[0].set_ylabel("first solution [ms] (median)")
    axes[0].set_title("environment: time to the first solution")
    axes[0].legend(fontsize=7)
    axes[1].set_xscale("log", base=2)
    axes[1].set_xlabel("map size (cells per side)")
    axes[1].set_ylabel("PRM cost / bang-bang lower bound (median)")
    axes[1].set_title("environment: anytime cost")
    axes[1].legend(fontsize=7)
    exp = [r for r in rows if r["experiment"] == "expansiveness"]
    xs = [r["prm"]["trapped_fraction"] for r in exp if r["prm"]["first_ms"] is not None]
    ys = [r["prm"]["first_ms"] for r in exp if r["prm"]["first_ms"] is not None]
    axes[2].scatter(xs, ys)
    for r in exp:
        if r["prm"]["first_ms"] is not None:
            axes[2].annotate("%s %g" % (r["kind"], r["pitch_max_deg"]),
                             (r["prm"]["trapped_fraction"], r["prm"]["first_ms"]), fontsize=6)
    axes[2].set_yscale("log")
    axes[2].set_xlabel("trapped fraction (expansiveness: higher is harder)")
    axes[2].set_ylabel("first solution [ms]")
    axes[2].set_title("expansiveness")
    for ax in axes:
        ax.grid(True, alpha=0.3)
    fig.suptitle(title(result))
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    return [png, peers(result, rows, png)]


def peers(result, rows, png):
    """OMPL's RRT and SST against the PRM on the same problems: time to the first solution,
    and cost (RRT: its only solution against the PRM's first; SST: at the budget against the
    PRM's at the budget)."""
    fig, axes = plt.subplots(1, 2, figsize=(12, 5.5))
    for peer, marker in [("ompl_rrt", "o"), ("ompl_sst", "s")]:
        xs, ys, cx, cy = [], [], [], []
        for r in rows:
            p = r.get(peer, {})
            if p.get("first_ms") is not None and r["prm"]["first_ms"] is not None:
                xs.append(r["prm"]["first_ms"])
                ys.append(p["first_ms"])
            if p.get("cost_final_s") is not None:
                prm_cost = r["prm"]["first_cost_s"] if peer == "ompl_rrt" else r["prm"]["cost_final_s"]
                if prm_cost is not None:
                    cx.append(prm_cost)
                    cy.append(p["cost_final_s"])
        axes[0].scatter(xs, ys, marker=marker, label=peer)
        axes[1].scatter(cx, cy, marker=marker,
                        label=peer + (" vs PRM first" if peer == "ompl_rrt" else " vs PRM at budget"))
    for ax in axes:
        lo, hi = ax.get_xlim()
        lo2, hi2 = ax.get_ylim()
        a, b = min(lo, lo2), max(hi, hi2)
        ax.plot([a, b], [a, b], "k-", lw=0.8, label="equal")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    axes[0].set_xscale("log")
    axes[0].set_yscale("log")
    axes[0].set_xlabel("PRM first solution [ms]")
    axes[0].set_ylabel("OMPL first solution [ms]")
    axes[0].set_title("time to the first solution (above the line: the PRM is faster)")
    axes[1].set_xlabel("PRM cost [s]")
    axes[1].set_ylabel("OMPL cost [s] (re-integrated)")
    axes[1].set_title("trajectory duration (above the line: the PRM is better)")
    fig.suptitle(title(result))
    fig.tight_layout()
    out = png[:-4] + "-peers.png" if png.endswith(".png") else png + "-peers.png"
    fig.savefig(out, dpi=110)
    return out


def refine(result, png):
    fig, ax = plt.subplots(figsize=(7, 6))
    top = 0.0
    for planner in ["prm_first", "prm_1s", "taeasl"]:
        xs, ys = [], []
        for r in result["rows"]:
            if r.get("planner") != planner:
                continue
            for c in r.get("candidates", []):
                if c.get("status") == "converged":
                    xs.append(c["candidate_s"])
                    ys.append(c["refined_s"])
        if xs:
            ax.scatter(xs, ys, label=planner, s=18)
            top = max(top, max(xs), max(ys))
    ax.plot([0, top], [0, top], "k-", lw=0.8, label="refined = candidate")
    ax.plot([0, top], [0, 0.9 * top], "k--", lw=0.8, label="0.9 x candidate")
    ax.set_xlabel("candidate duration [s]")
    ax.set_ylabel("refined duration [s]")
    ax.set_title(title(result))
    ax.legend()
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    return [png]


def tables(result, png):
    summary = result["summary"]["by_tables"]
    kinds = [k for k in ["none", "physics", "data"] if k in summary]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    axes[0].bar(kinds, [summary[k].get("traversal_time_s", {}).get("mean", 0.0) for k in kinds])
    axes[0].set_ylabel("traversal time [s] (mean)")
    axes[1].bar(kinds, [100 * summary[k].get("violating_data_tables", {}).get("mean", 0.0)
                        for k in kinds])
    axes[1].set_ylabel("states faster than the data-driven tables [%] (mean)")
    for ax in axes:
        ax.set_xlabel("tables the planner used")
        ax.grid(True, axis="y", alpha=0.3)
    fig.suptitle(title(result))
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    return [png]


def title(result):
    machine = result.get("machine", {})
    commit = (machine.get("commit") or "unknown")[:10]
    return "terratraj bench %s (%d rows, %s, commit %s)" % (
        result["suite"], len(result["rows"]), machine.get("host", "?"), commit)


def main():
    with open(sys.argv[1]) as f:
        request = json.load(f)
    with open(request["result"]) as f:
        result = json.load(f)
    draw = {"convergence": convergence, "planners": planners, "refine": refine,
            "tables": tables, "robustness": robustness}[result["suite"]]
    files = draw(result, request["png"])
    with open(request["files"], "w") as f:
        json.dump(files, f)


if __name__ == "__main__":
    main()
