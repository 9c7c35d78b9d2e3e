#!/usr/bin/python3
"""Checks of README.md and docs/*.md (ctest label docs).

  check_docs.py figures    ROOT [--mutate md|readme|json]
  check_docs.py references ROOT [--build DIR] [--mutate path|experiment|ctest|yaml|length|command]
  check_docs.py history    ROOT [--mutate WORD]

figures: every table of docs/results.md and the README's results table equal
  the tables scripts/tools/results_docs.py renders from docs/results/results.json
  (text compared); and results.json's figures equal ROOT/out/ (summary.json,
  compare.csv, the sweeps' csv, contour.json, rehearsal steps) when a run's
  out/ is there (skipped, with the reason printed, when ROOT/out/ holds no run).
references: every file path, experiment name (experiments.yaml key), ctest
  name and YAML key the documents name exists; README.md is at most 250 lines
  and has the two set-up commands exactly.
history: no document tells the history of its own making (HISTORY below).

--mutate runs the same check on a copy with one planted error and exits 0
only when the check finds it (the check must be able to fail).
"""
import argparse
import csv
import glob
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

README_MAX_LINES = 250
README_COMMANDS = ["bash scripts/run_experiment.sh", "bash scripts/run_tests.sh"]
# results.json keeps SIG = 4 significant digits: a stored figure is within half
# a unit of the 4th digit of the output's value (relative 5e-4).
REL_TOL = 5e-4
EXTS = (".md", ".sh", ".py", ".yaml", ".yml", ".ops", ".osd", ".cpf", ".xml", ".png", ".json",
        ".csv", ".hpp", ".cpp", ".h", ".txt", ".launch", ".rviz", ".urdf", ".src", ".dat", ".cmake", ".supp", ".ini", ".msg", ".srv", ".ops")
# Words that tell how a document or the code came to be, not what it is.
HISTORY = [r"\bsessions?\b", r"\bagents?\b", r"\bhelpers?\b", r"\bissue\s*#?\d+", r"\bpreviously\b",
           r"\bused to\b", r"\bwe fixed\b", r"\bthis commit\b", r"\bformerly\b", r"\bno longer\b",
           r"\bwas renamed\b", r"\bwere renamed\b", r"\bin the past\b", r"\bbefore the fix\b",
           r"\bwe (?:added|changed|removed|replaced|rewrote)\b", r"\bthe old (?:code|version|script)\b",
           r"\bfixed (?:a|the) bug\b", r"\bdiary\b", r"\buntil now\b", r"\bfirst attempt\b"]


def docs(root):
    return [os.path.join(root, "README.md")] + sorted(glob.glob(os.path.join(root, "docs", "*.md")))


def fail(errors, what):
    for e in errors:
        print("FAIL:", e)
    print(f"{what}: {len(errors)} error(s)" if errors else f"{what}: ok")
    return 1 if errors else 0


# ---------------- figures ----------------

def load_renderer(root):
    sys.dont_write_bytecode = True  # no __pycache__ in the source tree
    sys.path.insert(0, os.path.join(root, "scripts", "tools"))
    import results_docs  # noqa: E402
    return results_docs


def close(a, b):
    if isinstance(a, list) or isinstance(b, list):
        return isinstance(a, list) and isinstance(b, list) and len(a) == len(b) and all(close(x, y) for x, y in zip(a, b))
    if isinstance(b, bool) or a is None or b is None or isinstance(b, str) or isinstance(a, str):
        return a == b
    return abs(a - b) <= REL_TOL * abs(b) + 1e-12


def num(s):
    if s in (None, ""):
        return None
    try:
        v = float(s)
    except ValueError:
        return s
    return None if v != v else v


def against_out(res, out):
    """results.json's figures against the outputs they were read from."""
    err = []

    def cmp(where, key, stored, actual):
        if not close(stored, actual):
            err.append(f"results.json {where} {key} = {stored!r}, {out} has {actual!r}")

    for group, sub in (("runs", ""), ("deploy", "deploy")):
        for name, fig in res[group].items():
            p = os.path.join(out, sub, name, "summary.json")
            if not os.path.exists(p):
                err.append(f"{p}: missing (results.json has {group}.{name})")
                continue
            s = json.load(open(p))
            for k, v in fig.items():
                actual = [x["name"] for x in s.get("phases", [])] if k == "phases" else s.get(k)
                cmp(f"{group}.{name}", k, v, actual)
    for key, sub in (("shipped", "compare"), ("paper", "compare_paper")):
        rows = {(r["scene"], r["controller"]): r for r in csv.DictReader(open(os.path.join(out, sub, "compare.csv")))}
        if len(rows) != len(res["compare"][key]):
            err.append(f"{sub}/compare.csv: {len(rows)} rows, results.json {len(res['compare'][key])}")
        for r in res["compare"][key]:
            c = rows.get((r["scene"], r["controller"]), {})
            for k, v in r.items():
                cmp(f"compare.{key}.{r['scene']}.{r['controller']}", k, v, num(c.get(k)) if k not in ("scene", "controller", "status") else c.get(k))
    ft = list(csv.DictReader(open(os.path.join(out, "force_targets", "force_targets.csv"))))
    if [{k: r[k] for k in x} for r, x in zip(ft, res["force_targets"])] != res["force_targets"] or len(ft) != len(res["force_targets"]):
        err.append("force_targets: results.json differs from force_targets/force_targets.csv")
    fs = list(csv.DictReader(open(os.path.join(out, "force", "force.csv"))))
    for r, x in zip(fs, res["force_sweep"]):
        for k, v in x.items():
            cmp(f"force_sweep.{x['case']}", k, v, r[k] if k in ("case", "after_meets") else num(r[k]))
    cc = list(csv.DictReader(open(os.path.join(out, "correction", "correction.csv"))))
    for r, x in zip(cc, res["correction"]):
        for k, v in x.items():
            src = k if k in ("scene", "bound") else "shipped_" + k
            cmp(f"correction.{x['scene']}.{x['bound']}", k, v, r[src] if k in ("scene", "bound") else num(r[src]))
    for x in res["contours"]:
        d = os.path.join(out, x["set"], x["run"])
        c = json.load(open(os.path.join(d, "contour.json")))
        s = json.load(open(os.path.join(d, "summary.json")))
        for k, v in x.items():
            if k in ("set", "run", "sensor_effects"):
                continue
            cmp(f"contours.{x['set']}.{x['run']}", k, v, s.get(k) if k == "force_true_rms_error_n" else c.get(k))
    steps = [l.rstrip("\n").split("|") for l in open(os.path.join(out, "rehearsal", "steps.txt")) if l.count("|") >= 2]
    if [(int(a[0]), a[1], a[2]) for a in steps] != [(x["step"], x["name"], x["result"]) for x in res["rehearsal"]]:
        err.append("rehearsal: results.json differs from rehearsal/steps.txt")
    return err


def check_figures(root, out):
    rd = load_renderer(root)
    err = []
    res = json.load(open(os.path.join(root, "docs", "results", "results.json")))
    for k in ("commit", "machine"):
        if not res.get(k):
            err.append(f"results.json: no {k}")
    for k in ("uname", "cpu", "nproc"):
        if not res.get("machine", {}).get(k):
            err.append(f"results.json: machine has no {k}")
    md = open(os.path.join(root, "docs", "results.md")).read()
    want = rd.render_results_md(res)
    if md != want:
        a, b = md.splitlines(), want.splitlines()
        bad = next((i for i in range(max(len(a), len(b))) if i >= len(a) or i >= len(b) or a[i] != b[i]), None)
        err.append(f"docs/results.md line {bad + 1}: {a[bad] if bad < len(a) else '<end>'!r}, "
                   f"rendered from results.json: {b[bad] if bad < len(b) else '<end>'!r}")
    readme = open(os.path.join(root, "README.md")).read()
    i, j = readme.find(rd.BEGIN), readme.find(rd.END)
    if i < 0 or j < i:
        err.append("README.md: no results table markers")
    elif readme[i:j + len(rd.END)] != rd.readme_block(res):
        err.append("README.md: the results table differs from the one rendered from docs/results/results.json")
    if out and os.path.exists(os.path.join(out, "edge_exploration", "summary.json")):
        try:
            err += against_out(res, out)
        except OSError as e:  # an output results.json was read from is absent: a partial run
            err.append(f"{e.filename}: missing (out/ holds an incomplete run of scripts/run_experiment.sh)")
        print(f"figures: results.json checked against {out}")
    else:
        print(f"figures: {out}/edge_exploration/summary.json absent (no main-job run here): "
              "results.json not checked against out/, only the documents against results.json")
    return err


# ---------------- references ----------------

def experiments(root):
    keys, inside = set(), False
    for line in open(os.path.join(root, "experiments.yaml")):
        if line.startswith("experiments:"):
            inside = True
        elif inside:
            m = re.match(r"^  ([A-Za-z0-9_]+):", line)
            if m:
                keys.add(m.group(1))
    return keys


def ctest_names(build, root):
    """The tests the build configured, plus every add_test(NAME ...) of the
    tree's CMake files and its helpers' first arguments (a test the build leaves out, e.g. with the RTT layer
    off, still exists); a NAME with ${...} gives its literal prefix."""
    names, prefixes = set(), set()
    if build and os.path.isdir(build):
        p = subprocess.run(["ctest", "-N"], cwd=build, capture_output=True, text=True)
        names |= {m.group(1) for m in re.finditer(r"Test\s+#\d+: (\S+)", p.stdout)}
    for f in glob.glob(os.path.join(root, "**", "CMakeLists.txt"), recursive=True) + \
            glob.glob(os.path.join(root, "cmake", "*.cmake")):
        if "/build" in f[len(root):]:
            continue
        text = open(f, errors="replace").read()
        # add_test(NAME n ...) and the tree's helpers, e.g. tactile_deployer_test(n ...)
        for m in re.finditer(r"(?:\badd_test\(\s*NAME\s+|\b[a-z_]+_test\(\s*)([^\s)]+)", text):
            n = m.group(1)
            if n == "NAME" or n.startswith("$") and "}" == n[-1:]:
                continue
            if "${" in n:
                if n.index("${") > 0:
                    prefixes.add(n[:n.index("${")])
            else:
                names.add(n)
    return names, prefixes


def is_test(name, tests):
    names, prefixes = tests
    return name in names or any(name.startswith(p) for p in prefixes)


def yaml_keys(root):
    keys = set()
    for pat in ("experiments.yaml", "sim/scenes/*.yaml", "components/*/programs/*.yaml", "components/*/config/*.yaml",
                "components/*/calibration/*.yaml", "deployments/*.yaml", "deployments/*/*.yaml", "**/*.yaml"):
        for p in glob.glob(os.path.join(root, pat), recursive=True):
            if "/build/" in p or "/out/" in p:
                continue
            try:
                for line in open(p, errors="replace"):
                    m = re.match(r"^\s*-?\s*([A-Za-z0-9_]+):", line)
                    if m:
                        keys.add(m.group(1))
            except OSError:
                pass
    # the keys the parsers read: the string literals of the sources that read YAML
    for p in glob.glob(os.path.join(root, "**", "src", "*.cpp"), recursive=True):
        if "/build" in p:
            continue
        for m in re.finditer(r'"([a-z][a-z0-9_]*)"', open(p, errors="replace").read()):
            keys.add(m.group(1))
    return keys


def tracked_files(root):
    p = subprocess.run(["git", "-C", root, "ls-files"], capture_output=True, text=True)
    return p.stdout.splitlines() if p.returncode == 0 else []


def check_references(root, build, docroot=None):
    """docroot: where the documents are (default root; a mutated copy's), with root's files."""
    docroot = docroot or root
    err = []
    exps = experiments(root)
    tests = ctest_names(build, root)
    ykeys = yaml_keys(root)
    files = tracked_files(root)
    readme = os.path.join(docroot, "README.md")
    n = len(open(readme).read().splitlines())
    if n > README_MAX_LINES:
        err.append(f"README.md: {n} lines (at most {README_MAX_LINES})")
    lines = open(readme).read().splitlines()
    for cmd in README_COMMANDS:
        if cmd not in lines:
            err.append(f"README.md: no line `{cmd}` (the set-up commands, exactly)")
    for doc in docs(docroot):
        text = open(doc).read()
        rel = os.path.relpath(doc, docroot)
        docdir = os.path.join(root, os.path.dirname(rel))
        tokens = re.findall(r"`([^`\n]+)`", text) + re.findall(r"\]\(([^)\s#]+)(?:#[^)]*)?\)", text)
        for tok in tokens:
            for word in tok.split():
                w = word.strip("\"',;:()")
                if "://" in w or "<" in w or "*" in w or "$" in w or "{" in w or w.startswith(("/", "~", "-")):
                    continue
                if w.startswith(("out/", "build/", "runs/", "bin/", "install/")) or "/out/" in w:
                    continue  # generated
                if "/" in w.rstrip("/"):
                    # a path (a bare file name such as summary.json names a kind of file, not a
                    # path): relative to the root or the document, or an include path (the end of
                    # a file's path); a word without an extension whose first part is nothing in
                    # the tree is not a path (sensor_msgs/Image, N/count)
                    first = w.split("/")[0]
                    if not w.endswith(EXTS) and not any(os.path.exists(os.path.join(d, first)) for d in (root, docdir)):
                        continue
                    if not any(os.path.exists(os.path.join(d, w)) for d in (root, docdir)) \
                            and not any(f.endswith("/" + w) for f in files):
                        err.append(f"{rel}: `{w}`: no such file or folder")
            m = re.match(r"^(?:bash )?scripts/(?:run_deployment|run_robot)\.sh (\S+)", tok)
            if m and not m.group(1).startswith(("<", "-")) and m.group(1) not in exps:
                err.append(f"{rel}: `{tok}`: {m.group(1)} is not an experiment of experiments.yaml")
            m = re.match(r"^ctest (?:-R )?([A-Za-z0-9_]+)$", tok)
            if m and not is_test(m.group(1), tests) and not any(re.search(m.group(1), x) for x in tests[0]):
                err.append(f"{rel}: `{tok}`: no ctest of that name")
            m = re.match(r"^([a-z][a-z0-9_]*(?:\.[a-z][a-z0-9_]*)+)$", tok)
            if m and not tok.endswith(EXTS) and not tok.startswith(("tactile_", "std.")):
                for k in tok.split("."):
                    if k not in ykeys:
                        err.append(f"{rel}: `{tok}`: no YAML file of the repository has the key {k}")
                        break
        # experiment names written as "experiment `name`"
        for m in re.finditer(r"experiments? `([A-Za-z0-9_]+)`", text):
            if m.group(1) not in exps:
                err.append(f"{rel}: experiment `{m.group(1)}` is not a key of experiments.yaml")
        for m in re.finditer(r"ctest `([A-Za-z0-9_]+)`", text):
            if not is_test(m.group(1), tests):
                err.append(f"{rel}: ctest `{m.group(1)}`: no test of that name (build or CMake files)")
    if not (build and os.path.isdir(build)):
        print(f"references: no build directory ({build}): ctest names from the CMake files only")
    return err


# ---------------- history ----------------

def check_history(root):
    err = []
    pats = [re.compile(p, re.IGNORECASE) for p in HISTORY]
    for doc in docs(root):
        for no, line in enumerate(open(doc), 1):
            for p in pats:
                m = p.search(line)
                if m:
                    err.append(f"{os.path.relpath(doc, root)}:{no}: '{m.group(0)}' (tells how the document came to be)")
    return err


# ---------------- mutations ----------------

def copy_tree(root):
    tmp = tempfile.mkdtemp(prefix="check_docs_")
    for name in ("README.md", "experiments.yaml"):
        shutil.copy(os.path.join(root, name), tmp)
    shutil.copytree(os.path.join(root, "docs"), os.path.join(tmp, "docs"))
    os.makedirs(os.path.join(tmp, "scripts"))
    shutil.copytree(os.path.join(root, "scripts", "tools"), os.path.join(tmp, "scripts", "tools"))
    return tmp


def bump_first_figure(path, after):
    text = open(path).read()
    i = text.find(after)
    m = re.compile(r"\d+\.\d\d").search(text, i)
    d = str((int(m.group(0)[-1]) + 1) % 10)
    open(path, "w").write(text[:m.end() - 1] + d + text[m.end():])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("check", choices=["figures", "references", "history"])
    ap.add_argument("root")
    ap.add_argument("--out", default=None, help="the main job's outputs (default ROOT/out)")
    ap.add_argument("--build", default=None, help="the build directory (ctest names)")
    ap.add_argument("--mutate", default=None)
    a = ap.parse_args()
    root = os.path.abspath(a.root)
    out = a.out or os.path.join(root, "out")
    if a.mutate is None:
        if a.check == "figures":
            return fail(check_figures(root, out), "docs_figures")
        if a.check == "references":
            return fail(check_references(root, a.build), "docs_references")
        return fail(check_history(root), "docs_no_history")

    tmp = copy_tree(root)
    try:
        if a.check == "figures":
            if a.mutate == "md":
                bump_first_figure(os.path.join(tmp, "docs", "results.md"), "## Headless runs")
                err = check_figures(tmp, None)
            elif a.mutate == "readme":
                bump_first_figure(os.path.join(tmp, "README.md"), "RESULTS_BEGIN")
                err = check_figures(tmp, None)
            elif a.mutate == "json":
                if not os.path.exists(os.path.join(out, "edge_exploration", "summary.json")):
                    print(f"figures --mutate json: {out} holds no run; nothing to compare results.json with")
                    return 0
                p = os.path.join(tmp, "docs", "results", "results.json")
                res = json.load(open(p))
                res["runs"]["bent_bar"]["force_true_rms_error_n"] *= 1.01  # 1 % off: 20x the rounding tolerance
                json.dump(res, open(p, "w"))
                err = against_out(res, out)
            else:
                sys.exit(f"--mutate {a.mutate}: md | readme | json")
        elif a.check == "references":
            readme = os.path.join(tmp, "README.md")
            add = {"path": "See `scripts/no_such_tool.py`.\n",
                   "experiment": "Run `bash scripts/run_deployment.sh no_such_experiment`.\n",
                   "ctest": "Checked by ctest `no_such_test_name`.\n",
                   "yaml": "Set `force_estimate.no_such_key` in the program.\n",
                   "length": "x\n" * README_MAX_LINES,
                   "command": None}.get(a.mutate, "")
            if a.mutate == "command":
                text = open(readme).read().replace("\nbash scripts/run_tests.sh\n", "\nbash scripts/run_tests.sh -j2\n")
                open(readme, "w").write(text)
                add = ""
            elif add == "":
                sys.exit(f"--mutate {a.mutate}: path | experiment | ctest | yaml | length | command")
            open(readme, "a").write(add)
            # the copy holds only the documents: checked against the real tree's files
            err = check_references(root, a.build, docroot=tmp)
        else:
            open(os.path.join(tmp, "docs", "design.md"), "a").write(f"\nThis table was added {a.mutate}.\n")
            err = check_history(tmp)
        for e in err:
            print("found:", e)
        print(f"{a.check} --mutate {a.mutate}: " + ("the planted error was found" if err else "NOT found"))
        return 0 if err else 1
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
