#!/usr/bin/python3
"""Slope-dwell solves on the real DEMs, random start and goal: a check on problems outside the
robustness set (`bench robustness` solves the time cost only).

Usage: scripts/slope_dwell_campaign.py --seed 1 --count 20 --out-dir DIR
           [--exe build/apps/terratraj] [--data-dir ../shared/data] [--time-limit 60]

Each problem: a DEM (moon, davosdorf at 0.25 m cells and z x 0.0125, the gully at its 3 m cells
with slopes over 25 deg lethal, as the robustness set), a wheeled vehicle (point, four-wheel,
rocker-bogie), 4-12 m apart (12-36 m on the gully), headings within 60 deg of the line between,
at rest or at 0.5 m/s at both ends, `cost: slope_dwell` with alpha 1 or 2, every other key its
default. Problems `terratraj check` refuses are drawn again. Each converged CSV is re-checked
here against pitch, roll, v_max, kappa_max (1e-3 relative) and the goal (1 mm). One JSON line
per problem on stdout; DIR/rows<seed>.json at the end. Deterministic in --seed (the problems;
the solves' time limits are wall clock).
"""
import argparse
import csv
import json
import math
import os
import random
import subprocess

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--seed", type=int, required=True)
parser.add_argument("--count", type=int, required=True)
parser.add_argument("--out-dir", required=True)
parser.add_argument("--exe", default="build/apps/terratraj")
parser.add_argument("--data-dir", default="../shared/data")
parser.add_argument("--time-limit", type=float, default=60.0)
args = parser.parse_args()
os.makedirs(args.out_dir, exist_ok=True)
rng = random.Random(args.seed)
data = os.path.abspath(args.data_dir)
dems = [("dem_moon.tif", None, 1.0, None, 1.0),
        ("davosdorf.tif", 0.25, 0.0125, None, 1.0),
        ("west_bijou_gully.asc", None, 1.0, 25, 3.0)]
vehicles = ["point", "four_wheel", "rocker_bogie"]
PITCH_MAX, ROLL_MAX, V_MAX, KAPPA_MAX = math.radians(17), math.radians(20), 1.0, 1.0  # defaults


def extent(name, cell, z_scale):
    cmd = [args.exe, "terrain", "info", os.path.join(data, name), "--json", "--z-scale", str(z_scale)]
    if cell:
        cmd += ["--cell", str(cell)]
    e = json.loads(subprocess.run(cmd, capture_output=True, text=True, check=True).stdout)
    e = e["extent_local_m"]
    return e["x_min"], e["y_min"], e["x_max"], e["y_max"]


def csv_check(csv_path, goal):
    rows = list(csv.DictReader(open(csv_path)))
    worst = 0.0
    for r in rows:
        v = float(r["v"])
        worst = max(worst, abs(float(r["pitch"])) / PITCH_MAX, abs(float(r["roll"])) / ROLL_MAX,
                    v / V_MAX, abs(float(r["curvature"])) / KAPPA_MAX if v > 1e-3 else 0.0)
    miss = math.hypot(float(rows[-1]["x"]) - goal["x"], float(rows[-1]["y"]) - goal["y"])
    return worst, miss


extents = {d[0]: extent(d[0], d[1], d[2]) for d in dems}
results = []
made = 0
while made < args.count:
    name, cell, z_scale, lethal_slope, scale = rng.choice(dems)
    x0, y0, x1, y1 = extents[name]
    distance = rng.uniform(4, 12) * scale
    sx, sy = rng.uniform(x0 + 2 * scale, x1 - 2 * scale), rng.uniform(y0 + 2 * scale, y1 - 2 * scale)
    angle = rng.uniform(-math.pi, math.pi)
    gx, gy = sx + distance * math.cos(angle), sy + distance * math.sin(angle)
    if not (x0 + 2 * scale < gx < x1 - 2 * scale and y0 + 2 * scale < gy < y1 - 2 * scale):
        continue
    rest = rng.random() < 0.5
    speed = 0.0 if rest else 0.5
    vehicle = rng.choice(vehicles)
    alpha = rng.choice([1.0, 2.0])
    terrain = {"file": os.path.join(data, name), "z_scale": z_scale}
    if cell:
        terrain["cell"] = cell
    if lethal_slope:
        terrain["obstacles"] = {"max_slope_deg": lethal_slope}
    heading = math.degrees(angle)
    problem = {"terrain": terrain, "vehicle": {"model": vehicle},
               "start": {"x": sx, "y": sy, "heading_deg": heading + rng.uniform(-60, 60), "v": speed},
               "goal": {"x": gx, "y": gy, "heading_deg": heading + rng.uniform(-60, 60), "v": speed},
               "cost": {"kind": "slope_dwell", "alpha": alpha},
               "solver": {"time_limit_s": args.time_limit}}
    path = os.path.join(args.out_dir, f"p{args.seed}_{made}.yaml")
    with open(path, "w") as f:
        json.dump(problem, f)  # JSON is YAML
    if subprocess.run([args.exe, "check", path], capture_output=True).returncode != 0:
        continue
    made += 1
    csv_path = path.replace(".yaml", ".csv")
    run = subprocess.run([args.exe, "solve", path, "--json", "--out", csv_path],
                         capture_output=True, text=True)
    report = json.loads(run.stdout) if run.stdout.strip() else {}
    row = dict(path=path, exit=run.returncode, vehicle=vehicle, dem=name, rest=rest,
               status=report.get("status"), reason=(report.get("reason") or "")[:200],
               cost=report.get("cost"), ms=report.get("solve_time_ms"), method=report.get("method"))
    if row["status"] == "converged":
        row["limit_ratio"], row["goal_miss_m"] = csv_check(csv_path, problem["goal"])
        row["csv_ok"] = row["limit_ratio"] <= 1.001 and row["goal_miss_m"] <= 1e-3
    results.append(row)
    print(json.dumps(row), flush=True)
with open(os.path.join(args.out_dir, f"rows{args.seed}.json"), "w") as f:
    json.dump(results, f, indent=1)
