#!/usr/bin/python3
"""Summarise tactile_features JSON output against the sample's analytic truth.

usage: feature_summary.py FEATURES.jsonl TRUTH.csv
"""
import csv
import json
import math
import sys


def main():
    feats = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
    truth = list(csv.DictReader(open(sys.argv[2])))
    if len(feats) != len(truth):
        sys.exit(f"feature_summary: {len(feats)} feature lines but {len(truth)} truth rows")
    kinds = {}
    cop_err = []
    angle_err = []
    for f, t in zip(feats, truth):
        kinds[f["contact"]] = kinds.get(f["contact"], 0) + 1
        if f["contact"] == "none":
            continue
        cop_err.append(math.hypot(f["cop_x"] - float(t["cop_x_true"]), f["cop_y"] - float(t["cop_y_true"])))
        if t["kind"] == "edge" and f["contact"] == "edge":
            d = (f["alpha_z"] - float(t["angle"]) + math.pi / 2) % math.pi - math.pi / 2
            angle_err.append(abs(d))
    print(f"frames: {len(feats)}  contact types: {kinds}")
    if cop_err:
        print(f"CoP error vs analytic pressure centre: mean {1e3 * sum(cop_err) / len(cop_err):.3f} mm, "
              f"max {1e3 * max(cop_err):.3f} mm")
    if angle_err:
        print(f"edge angle error: mean {math.degrees(sum(angle_err) / len(angle_err)):.2f} deg, "
              f"max {math.degrees(max(angle_err)):.2f} deg")


if __name__ == "__main__":
    main()
