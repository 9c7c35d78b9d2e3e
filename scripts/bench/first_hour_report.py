#!/usr/bin/python3
"""Writes the first-hour report from the logs of scripts/bench/fresh_machine.sh.

Reads LOGS/{test_command,main_job,setup_only}.log (each line: UTC time,
seconds since the command's start, the command's own line), LOGS/*.time
("wall user sys exit-code"), LOGS/loadavg.log and LOGS/uptime-*.txt, and
writes the Markdown page and the JSON record. From the test command's own
lines: "run_tests: set-up took N s", "run_tests: set-up and build took N s",
"run_tests: total N s", and every "<script>: <stage> done in N s".

  first_hour_report.py --logs DIR --commit HASH --md FILE --json FILE [--jobs N] [--stop-after STAGE]
  first_hour_report.py --placeholder --md FILE --json FILE

Exit code 1 when the test command failed or a budget was missed (for
--stop-after: when the set-up failed), 0 otherwise.
"""
import argparse
import datetime
import json
import os
import re
import subprocess
import sys

BUDGET_MAIN_S = 20 * 60   # the main job's first result, set-up and build included
BUDGET_TESTS_S = 30 * 60  # the test command green

LINE = re.compile(r"^(\d\d:\d\d:\d\d) +(\d+\.\d+) (.*)$")
# "<script>: <stage> done in N s" or "... took N s", anything after it (a CPU
# figure, a log's path) allowed; the test command's own totals are read apart.
STAGE_DONE = re.compile(r"^([\w.-]+): +(.+?) (?:done in|took) (\d+(?:\.\d+)?) ?s\b")
TOTALS = ("run_tests", "ci")
CTEST = re.compile(r"(\d+)% tests passed, (\d+) tests? failed out of (\d+)")


def slurp(path):
    with open(path, errors="replace") as f:
        return f.read()


def read_log(path):
    """[(seconds since start, text)] of a timestamped log; [] when absent."""
    rows = []
    if not os.path.exists(path):
        return rows
    for raw in slurp(path).splitlines():
        m = LINE.match(raw)
        if m:
            rows.append((float(m.group(2)), m.group(3)))
    return rows


def read_time(path):
    """{'wall','user','sys','cpu','rc'} from a .time file; None when absent."""
    if not os.path.exists(path):
        return None
    parts = slurp(path).split()
    if len(parts) != 4:
        return None
    wall, user, sys_s = (float(x) for x in parts[:3])
    return {"wall_s": wall, "user_s": user, "sys_s": sys_s,
            "cpu_s": round(user + sys_s, 2), "exit_code": int(parts[3])}


def first_int(rows, pattern):
    rx = re.compile(pattern)
    for _, text in rows:
        m = rx.search(text)
        if m:
            return int(m.group(1))
    return None


def first_time(rows, pattern):
    """Seconds since start of the first line matching pattern, or None."""
    rx = re.compile(pattern)
    for t, text in rows:
        if rx.search(text):
            return t
    return None


def stage_lines(rows):
    out = []
    for _, text in rows:
        m = STAGE_DONE.match(text)
        if m and m.group(1) not in TOTALS:
            sec = float(m.group(3))
            out.append({"script": m.group(1), "stage": m.group(2).strip(),
                        "s": int(sec) if sec.is_integer() else sec})
    return out


def parse_test_command(rows):
    """Set-up, build, tests and total seconds from the test command's own lines;
    where a line is missing, from the timestamps of the lines that follow it."""
    setup = first_int(rows, r"^run_tests: set-up took (\d+) s")
    if setup is None:
        t = first_time(rows, r"^build: configuring")
        setup = round(t) if t is not None else None
    setup_build = first_int(rows, r"^run_tests: set-up and build took (\d+) s")
    if setup_build is None:
        t = first_time(rows, r"^run_tests: \d+ RTT tests configured|^Test project ")
        setup_build = round(t) if t is not None else None
    total = first_int(rows, r"^run_tests: total (\d+) s")
    ctest = None
    for _, text in rows:
        m = CTEST.search(text)
        if m:
            ctest = {"passed_percent": int(m.group(1)), "failed": int(m.group(2)),
                     "total": int(m.group(3))}
    out = {"setup_s": setup, "build_s": None, "tests_s": None, "run_tests_total_s": total,
           "ci_total_s": first_int(rows, r"^ci: total (\d+) s"), "ctest": ctest}
    if setup is not None and setup_build is not None:
        out["build_s"] = setup_build - setup
    if setup_build is not None and total is not None:
        out["tests_s"] = total - setup_build
    return out


def load_stats(logs, jobs):
    rows = []
    path = os.path.join(logs, "loadavg.log")
    if os.path.exists(path):
        for line in slurp(path).splitlines():
            p = line.split()
            if len(p) >= 2:
                rows.append((p[0], float(p[1])))
    up = {}
    for k in ("start", "end"):
        f = os.path.join(logs, f"uptime-{k}.txt")
        up[k] = slurp(f).strip() if os.path.exists(f) else None
    loads = [x for _, x in rows]
    stats = {"samples": len(loads), "mean_1min": None, "max_1min": None,
             "uptime_start": up["start"], "uptime_end": up["end"], "per_minute": rows}
    if loads:
        stats["mean_1min"] = round(sum(loads) / len(loads), 2)
        stats["max_1min"] = max(loads)
    # The benchmark's own build keeps about `jobs` processes runnable.
    stats["shared"] = bool(loads) and stats["mean_1min"] > jobs + 1.0
    return stats


def machine():
    def run(cmd):
        try:
            return subprocess.run(cmd, capture_output=True, text=True, check=False).stdout.strip()
        except OSError:
            return ""
    model = ""
    for line in run(["lscpu"]).splitlines():
        if line.startswith("Model name:"):
            model = line.split(":", 1)[1].strip()
    return {"uname": run(["uname", "-srm"]), "cpu": model, "nproc": int(run(["nproc"]) or 0)}


def verdict(ok, over_text):
    return "pass" if ok else over_text


def full_record(logs, rec):
    tc_rows = read_log(os.path.join(logs, "test_command.log"))
    mj_rows = read_log(os.path.join(logs, "main_job.log"))
    tc = parse_test_command(tc_rows)
    tc_time = read_time(os.path.join(logs, "test_command.time"))
    mj_time = read_time(os.path.join(logs, "main_job.time"))
    first = first_time(mj_rows, r"^results: ")
    rec["stages"] = dict(tc, test_command=tc_time, main_job=mj_time,
                         main_job_to_first_result_s=first)
    rec["setup_details"] = stage_lines(tc_rows)
    main_first = first  # the main job runs on its own fresh root: set-up and build included
    rec["stages"]["main_job_first_result_s"] = main_first
    rec["main_job_details"] = stage_lines(mj_rows)
    tests_ok = tc_time is not None and tc_time["exit_code"] == 0
    if tc_time is None:
        v_tests = "not run"
    elif not tests_ok:
        v_tests = f"FAIL (exit code {tc_time['exit_code']})"
    else:
        v_tests = verdict(tc_time["wall_s"] <= BUDGET_TESTS_S, "OVER BUDGET")
    if main_first is None:
        v_main = "FAIL (no `results:` line)" if mj_time else "not run"
    else:
        v_main = verdict(main_first <= BUDGET_MAIN_S, "OVER BUDGET")
    rec["verdicts"] = {"test_command": v_tests, "main_job_first_result": v_main}
    return v_tests == "pass" and v_main == "pass"


def partial_record(logs, rec, stop_after):
    rows = read_log(os.path.join(logs, "setup_only.log"))
    t = read_time(os.path.join(logs, "setup_only.time"))
    rec["stages"] = {"setup_only": t}
    rec["setup_details"] = stage_lines(rows)
    ok = t is not None and t["exit_code"] == 0
    rec["verdicts"] = {"setup_only": "ok" if ok else "FAIL",
                       "test_command": f"not measured (--stop-after {stop_after})",
                       "main_job_first_result": f"not measured (--stop-after {stop_after})"}
    return ok


def fmt(x):
    if x is None:
        return "—"
    if isinstance(x, float):
        return f"{x:.0f}" if x >= 10 else f"{x:.1f}"
    return str(x)


def cpu(t):
    return fmt(t["cpu_s"]) if t else "—"


def wall(t):
    return fmt(t["wall_s"]) if t else "—"


def stage_table(rec):
    s, v = rec["stages"], rec["verdicts"]
    if "setup_only" in s:
        t = s["setup_only"]
        return ["| stage | wall s | CPU s (user+sys) | budget s | verdict |", "|---|---|---|---|---|",
                f"| set-up scripts only ({rec['stop_after']}) | {wall(t)} | {cpu(t)} | — | {v['setup_only']} |",
                f"| test command | — | — | {BUDGET_TESTS_S} | {v['test_command']} |",
                f"| main job, first result | — | — | {BUDGET_MAIN_S} | {v['main_job_first_result']} |"]
    tc, mj = s.get("test_command"), s.get("main_job")
    return [
        "| stage | wall s | CPU s (user+sys) | budget s | verdict |", "|---|---|---|---|---|",
        f"| set-up (Debian packages, Orocos, rtt_ros) | {fmt(s.get('setup_s'))} | | | |",
        f"| build | {fmt(s.get('build_s'))} | | | |",
        f"| tests (ctest) | {fmt(s.get('tests_s'))} | | | |",
        f"| **test command** (`CI=true bash .ci/run`), in all | {wall(tc)} | {cpu(tc)} | {BUDGET_TESTS_S} | {v['test_command']} |",
        f"| **main job's first result** (`--quick`, its own fresh root: its first `results:` line) | {fmt(s.get('main_job_first_result_s'))} | | {BUDGET_MAIN_S} | {v['main_job_first_result']} |",
        f"| main job (`--quick`) in all, deployments included | {wall(mj)} | {cpu(mj)} | | |"]


def load_text(rec):
    ld = rec["load"]
    if ld is None:
        return ["Host load: not measured yet."]
    lines = [f"Host load during the run (1-min load average of `/proc/loadavg`, sampled each minute, "
             f"{ld['samples']} samples): mean {fmt(ld['mean_1min'])}, max {fmt(ld['max_1min'])}, "
             f"on {rec['machine']['nproc']} cores; the benchmark itself keeps about {rec['jobs']} busy.",
             f"`uptime` at the start: `{ld['uptime_start']}`; at the end: `{ld['uptime_end']}`.", ""]
    if ld["shared"]:
        lines.append("**The machine was shared during this run**: other processes kept the load above "
                     "the benchmark's own, so the wall times above are inflated; the CPU seconds are less so.")
    else:
        lines.append("The load stayed near the benchmark's own: the machine was not noticeably shared. "
                     "Another process on the machine would inflate the wall times.")
    return lines


def render_md(rec):
    m = rec["machine"]
    out = ["# The first hour on a fresh machine", "",
           "Generated by `scripts/bench/fresh_machine.sh` (do not edit by hand): a fresh Debian 12 root "
           "made with debootstrap, with only what a new machine has before the project (g++, CMake, "
           "git, python3, GoogleTest, Google Benchmark and the usual C++ tools; no Orocos, no ROS, no "
           "build tree, no ccache), a clone of the repository at the commit below and the pinned "
           "third-party archives beside it; in it, under `chroot`, the main job "
           "(`bash scripts/run_experiment.sh --quick`), then in another such root the test command "
           "(`CI=true bash .ci/run`).", "",
           f"Budgets: the test command green within {BUDGET_TESTS_S // 60} min; the main job's first "
           f"`results:` line within {BUDGET_MAIN_S // 60} min of a fresh start, set-up and build included. "
           "Measure (as root, apt reachable, the cores otherwise idle): `bash scripts/bench/fresh_machine.sh`; "
           "the base root is made once and kept as a tarball.", "",
           "| | |", "|---|---|",
           f"| status | {rec['status']} |",
           f"| commit | {fmt(rec['commit'])} |",
           f"| date (UTC) | {fmt(rec['date'])} |",
           f"| machine | {fmt(m['uname'])}; {fmt(m['cpu'])}; nproc {fmt(m['nproc'])}; jobs {fmt(rec['jobs'])} |", ""]
    out += stage_table(rec)
    if rec["stages"].get("ctest"):
        c = rec["stages"]["ctest"]
        out += ["", f"ctest: {c['passed_percent']}% tests passed, {c['failed']} failed out of {c['total']}."]
    if rec["setup_details"]:
        out += ["", "Set-up stages as the set-up scripts print them:", "",
                "| script | stage | s |", "|---|---|---|"]
        out += [f"| {d['script']} | {d['stage']} | {d['s']} |" for d in rec["setup_details"]]
    if rec.get("main_job_details"):
        out += ["", "The main job's stages (the simulator built alone, the headless experiments, then "
                "Orocos and the whole build):", "", "| script | stage | s |", "|---|---|---|"]
        out += [f"| {d['script']} | {d['stage']} | {d['s']} |" for d in rec["main_job_details"]]
    out += [""] + load_text(rec) + [""]
    return "\n".join(out)


def placeholder_record():
    return {"status": "not yet measured", "commit": None, "date": None, "jobs": None,
            "machine": {"uname": None, "cpu": None, "nproc": None}, "load": None,
            "budgets": {"test_command_s": BUDGET_TESTS_S, "main_job_first_result_s": BUDGET_MAIN_S},
            "stages": {}, "setup_details": [],
            "verdicts": {"test_command": "not yet measured", "main_job_first_result": "not yet measured"}}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--logs")
    ap.add_argument("--commit")
    ap.add_argument("--jobs", type=int)
    ap.add_argument("--stop-after", choices=["deps", "setup", "build"])
    ap.add_argument("--placeholder", action="store_true")
    ap.add_argument("--md", required=True)
    ap.add_argument("--json", required=True)
    a = ap.parse_args()
    if a.placeholder:
        rec, ok = placeholder_record(), True
    else:
        if not a.logs or not os.path.isdir(a.logs):
            sys.exit(f"first_hour_report: --logs {a.logs}: no such folder")
        rec = placeholder_record()
        jobs = a.jobs or os.cpu_count()
        rec.update(status="measured" if not a.stop_after else f"partial (--stop-after {a.stop_after})",
                   commit=a.commit, jobs=jobs, machine=machine(), stop_after=a.stop_after,
                   date=datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M"))
        rec["load"] = load_stats(a.logs, jobs)
        ok = partial_record(a.logs, rec, a.stop_after) if a.stop_after else full_record(a.logs, rec)
    for path in (a.md, a.json):
        os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with open(a.json, "w") as f:
        json.dump(rec, f, indent=2)
        f.write("\n")
    with open(a.md, "w") as f:
        f.write(render_md(rec))
    print(f"first_hour_report: {rec['status']}; test command: {rec['verdicts']['test_command']}; "
          f"main job's first result: {rec['verdicts']['main_job_first_result']}; wrote {a.md}, {a.json}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
