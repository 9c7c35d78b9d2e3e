#!/usr/bin/python3
"""Contact drops while sliding: the servo cycles of the given phases (default
explore) whose tactile image read no contact (timeseries.csv, contact == 0),
summed over the runs given. Exits 1 when the sum exceeds --max.

A drop is a cycle in which every taxel is below the firing threshold while the
pad still presses the object (the true force is on target): the servo then
searches instead of following. Usage:
  check_contact_drops.py RUN_DIR [RUN_DIR ...] [--phases explore] [--max N]
"""
import argparse
import csv
import sys


def drops(run_dir, phases):
    """(drop cycles, their times) of one run."""
    times = []
    with open(f"{run_dir}/timeseries.csv", newline="") as fh:
        for row in csv.DictReader(fh):
            if row["phase_name"] in phases and row["contact"] == "0":
                times.append(float(row["time"]))
    return times


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("runs", nargs="+", help="tactile_sim run output directories")
    ap.add_argument("--phases", default="explore", help="comma-separated phase names scored (default explore)")
    ap.add_argument("--max", type=int, default=0, help="largest number of drop cycles allowed over all runs")
    a = ap.parse_args()
    phases = set(a.phases.split(","))
    total = 0
    for d in a.runs:
        t = drops(d, phases)
        total += len(t)
        print(f"{d}: {len(t)} drop cycles while sliding at t = {', '.join(f'{x:.2f}' for x in t) or '-'} s")
    print(f"total {total} (max {a.max})")
    return 0 if total <= a.max else 1


if __name__ == "__main__":
    sys.exit(main())
