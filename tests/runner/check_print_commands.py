"""ctest tactile_sim_print_commands: what `tactile_sim program`, `scene` and
`schema` print, on the shipped files. `program` gives an overlay's program
with its chain of bases merged (the shared base's keys under a root's own);
`scene` gives the scene and its program with the --set overrides applied,
a program key among them, and refuses a bad value with exit 2 and the
program's file and key; `schema` prints a table row for every declared key.
Usage: check_print_commands.py TACTILE_SIM REPO."""
import subprocess
import sys

import yaml

sim, root = sys.argv[1:3]
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def run(*args):
    return subprocess.run([sim, *args], capture_output=True, text=True)


p = run("program", f"{root}/params/programs/bent_bar_speed_law.yaml")
prog = yaml.safe_load(p.stdout) if p.returncode == 0 else {}
check(p.returncode == 0 and prog["safety"]["max_trans_speed"] == 0.12, "program: the overlay's own value")
check(prog.get("controller", {}).get("c_z") == 0.000555556 and prog["safety"]["workspace"]["max"] == [0.9, 0.9, 1.2],
      "program: the shared base's keys, two bases down (bent_bar_to_end_cap -> bent_bar -> common)")
check("base" not in prog and "add_phases" not in prog and [x["name"] for x in prog["phases"]][-1] == "end_check",
      "program: no base or add_phases left, the added phase last")

s = run("scene", f"{root}/params/scenes/bent_bar_speed_law.yaml", "--set", "duration=3",
        "--set", "program.speed_law.force_budget_n=0.45", "--set", "program.phases.explore.kp_per_s.x=2.5")
docs = list(yaml.safe_load_all(s.stdout)) if s.returncode == 0 else []
check(len(docs) == 2, f"scene: two documents (exit {s.returncode}: {s.stderr.strip()})")
if len(docs) == 2:
    scene, sp = docs
    check(scene["duration"] == 3, "scene: a scene key set")
    check(sp["speed_law"]["force_budget_n"] == 0.45, "scene: a program key set")
    explore = next(x for x in sp["phases"] if x["name"] == "explore")
    check(explore["kp_per_s"]["x"] == 2.5 and "controller" in sp, "scene: a phase's key set by the phase's name")
bad = run("scene", f"{root}/params/scenes/bent_bar_speed_law.yaml", "--set", "program.speed_law.v_max=2")
check(bad.returncode == 2 and "bent_bar_speed_law.yaml: speed_law.v_max = 2: must be in (0, 1] m/s" in bad.stderr,
      f"scene: a value out of range refused naming the program, the key and the range ({bad.stderr.strip()})")

# The run's program: the registry's for the scene, or the one --program names.
own = run("scene", f"{root}/params/scenes/short_bar.yaml", "--program", f"{root}/params/programs/hold_edge_paper.yaml")
named = run("program", f"{root}/params/programs/hold_edge_paper.yaml")
check(own.returncode == 0 and list(yaml.safe_load_all(own.stdout))[1] == yaml.safe_load(named.stdout),
      f"scene --program: the program named, not the registry's ({own.stderr.strip()})")
reg = run("scene", f"{root}/params/scenes/short_bar.yaml", "--registry", f"{root}/tests/rtt/deploy/bad_registry.yaml")
check(reg.returncode == 2 and "no program for the scene" in reg.stderr,
      f"scene --registry: a registry that binds no program to the scene is an error ({reg.stderr.strip()})")

t = run("schema", "program")
check(t.returncode == 0 and "| `contact_loss.mode` |" in t.stdout and "| `crawl_after_s` |" in t.stdout,
      "schema program: the declared keys")
t = run("schema", "scene")
check(t.returncode == 0 and "| `noise_counts` | counts | [0, 1000] | 6 |" in t.stdout, "schema scene: the declared keys")
t = run("schema", "sensor")
check(t.returncode == 0 and "| `edge_ratio` |  | >= 1 | 5 |" in t.stdout, "schema sensor: the declared keys")
t = run("schema", "registry")
check(t.returncode == 0 and "| `timeout_s` | s | > 0; required | 60 |" in t.stdout, "schema registry: the declared keys")
check(run("schema", "world").returncode == 2, "schema: an unknown block set refused")
sys.exit(1 if failures else 0)
