#!/usr/bin/python3
"""Checks of scripts/bench/first_hour_report.py on logs made here, in the format
scripts/bench/fresh_machine.sh writes (its own stamp_lines makes them), whose
stage seconds are known: the sums, the budgets' verdicts, the exit codes, the
fall-back to timestamps, the load note and the placeholder.

  test_first_hour_report.py ROOT
"""
import json
import os
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.abspath(sys.argv.pop(1) if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", ".."))
REPORT = os.path.join(ROOT, "scripts", "bench", "first_hour_report.py")
BENCH = os.path.join(ROOT, "scripts", "bench", "fresh_machine.sh")


def stamped(lines_at):
    """[(seconds, text)] -> the lines as fresh_machine.sh's stamp_lines writes them,
    with the start moved back so that each line carries its given seconds."""
    out = []
    for t, text in lines_at:
        start_us = "$(( ${EPOCHREALTIME/./} - %d ))" % int(round(t * 1e6))
        script = f'source "{BENCH}"; s={start_us}; printf "%s\\n" "$1" | stamp_lines "$s"'
        r = subprocess.run(["bash", "-c", script, "x", text], capture_output=True, text=True, check=True)
        out.append(r.stdout)
    return "".join(out)


def write_logs(d, test_lines, test_rc, main_lines, loads, wall=1500.0):
    with open(os.path.join(d, "test_command.log"), "w") as f:
        f.write(stamped(test_lines))
    with open(os.path.join(d, "test_command.time"), "w") as f:
        f.write(f"{wall} 2000.5 300.25 {test_rc}\n")
    if main_lines is not None:
        with open(os.path.join(d, "main_job.log"), "w") as f:
            f.write(stamped(main_lines))
        with open(os.path.join(d, "main_job.time"), "w") as f:
            f.write("120.0 150.0 20.0 0\n")
    with open(os.path.join(d, "loadavg.log"), "w") as f:
        for i, x in enumerate(loads):
            f.write(f"15:{i:02d}:00 {x} 1.00 1.00 3/200 1234\n")


def slurp(path):
    with open(path) as f:
        return f.read()


def run_report(d, *extra):
    md, js = os.path.join(d, "out.md"), os.path.join(d, "out.json")
    r = subprocess.run(["/usr/bin/python3", REPORT, "--logs", d, "--commit", "abc123", "--jobs", "2",
                        "--md", md, "--json", js, *extra], capture_output=True, text=True)
    return r.returncode, json.loads(slurp(js)), slurp(md)


TEST_LINES = [(1, "setup_deps: installing build-essential"),
              (250, "setup_orocos:   rtt done in 180 s"),
              (260, "setup_rtt_ros: [4/5] catkin build took 35 s (cpu 60 s; log /tmp/x.log)"),
              (300, "run_tests: set-up took 300 s"),
              (301, "build: configuring (TACTILE_WITH_RTT=ON)"),
              (900, "run_tests: set-up and build took 900 s"),
              (1490, "100% tests passed, 0 tests failed out of 412"),
              (1490, "run_tests: total 1490 s"),
              (1495, "ci: total 1495 s")]
MAIN_LINES = [(3, "setup_deps: all 14 packages present"),
              (42.5, "results: /srv/fresh/tactile_servo/out/edge_exploration"),
              (50, "results: /srv/fresh/tactile_servo/out/bent_bar"),
              (300, "setup_orocos:   rtt done in 170 s")]


class Report(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.d = self.tmp.name

    def tearDown(self):
        self.tmp.cleanup()

    def test_within_budgets(self):
        write_logs(self.d, TEST_LINES, 0, MAIN_LINES, [2.1, 2.3])
        rc, rec, md = run_report(self.d)
        s = rec["stages"]
        self.assertEqual((s["setup_s"], s["build_s"], s["tests_s"]), (300, 600, 590))
        # The stamp keeps milliseconds; the shell's clock between the two reads
        # adds well under 0.5 s (tolerance of the line's seconds).
        self.assertAlmostEqual(s["main_job_to_first_result_s"], 42.5, delta=0.5)
        # The main job runs on its own fresh root: its first `results:` line is the measurement.
        self.assertAlmostEqual(s["main_job_first_result_s"], 42.5, delta=0.5)
        self.assertEqual(rec["main_job_details"], [{"script": "setup_orocos", "stage": "rtt", "s": 170}])
        self.assertEqual(s["test_command"]["cpu_s"], 2300.75)
        self.assertEqual(s["ctest"], {"passed_percent": 100, "failed": 0, "total": 412})
        self.assertEqual(rec["setup_details"], [{"script": "setup_orocos", "stage": "rtt", "s": 180},
                                                {"script": "setup_rtt_ros", "stage": "[4/5] catkin build", "s": 35}])
        self.assertEqual(rec["verdicts"], {"test_command": "pass", "main_job_first_result": "pass"})
        self.assertEqual(rc, 0)
        self.assertFalse(rec["load"]["shared"])
        self.assertIn("not noticeably shared", md)

    def test_main_job_over_budget(self):
        write_logs(self.d, TEST_LINES, 0, [(1210.0, "results: out/edge_exploration")], [2.0])
        rc, rec, _ = run_report(self.d)
        self.assertAlmostEqual(rec["stages"]["main_job_first_result_s"], 1210, delta=0.5)
        self.assertEqual(rec["verdicts"]["main_job_first_result"], "OVER BUDGET")
        self.assertEqual(rc, 1)

    def test_test_command_over_budget_and_failed(self):
        write_logs(self.d, TEST_LINES, 0, MAIN_LINES, [2.0], wall=1800.5)
        rc, rec, _ = run_report(self.d)
        self.assertEqual((rec["verdicts"]["test_command"], rc), ("OVER BUDGET", 1))
        write_logs(self.d, TEST_LINES, 8, MAIN_LINES, [2.0])
        rc, rec, _ = run_report(self.d)
        self.assertEqual((rec["verdicts"]["test_command"], rc), ("FAIL (exit code 8)", 1))

    def test_no_result_line(self):
        write_logs(self.d, TEST_LINES, 0, [(3, "setup_deps: all 14 packages present")], [2.0])
        rc, rec, _ = run_report(self.d)
        self.assertEqual((rec["verdicts"]["main_job_first_result"], rc), ("FAIL (no `results:` line)", 1))

    def test_setup_from_timestamps_when_its_line_is_missing(self):
        lines = [x for x in TEST_LINES if not x[1].startswith("run_tests: set-up took")]
        write_logs(self.d, lines, 0, MAIN_LINES, [2.0])
        _, rec, _ = run_report(self.d)
        self.assertEqual((rec["stages"]["setup_s"], rec["stages"]["build_s"]), (301, 599))

    def test_shared_machine_said(self):
        write_logs(self.d, TEST_LINES, 0, MAIN_LINES, [5.0, 6.0, 4.0])
        _, rec, md = run_report(self.d)
        self.assertEqual((rec["load"]["mean_1min"], rec["load"]["max_1min"]), (5.0, 6.0))
        self.assertTrue(rec["load"]["shared"])
        self.assertIn("The machine was shared during this run", md)

    def test_partial_run(self):
        with open(os.path.join(self.d, "setup_only.log"), "w") as f:
            f.write(stamped([(61, "fresh_machine: scripts/setup/setup_deps.sh done in 61 s")]))
        with open(os.path.join(self.d, "setup_only.time"), "w") as f:
            f.write("62.0 20.0 10.0 0\n")
        rc, rec, _ = run_report(self.d, "--stop-after", "deps")
        self.assertEqual(rc, 0)
        self.assertEqual(rec["setup_details"][0]["s"], 61)
        self.assertEqual(rec["verdicts"]["test_command"], "not measured (--stop-after deps)")

    def test_placeholder(self):
        md, js = os.path.join(self.d, "p.md"), os.path.join(self.d, "p.json")
        r = subprocess.run(["/usr/bin/python3", REPORT, "--placeholder", "--md", md, "--json", js])
        self.assertEqual(r.returncode, 0)
        self.assertEqual(json.loads(slurp(js))["status"], "not yet measured")
        self.assertIn("| status | not yet measured |", slurp(md))


if __name__ == "__main__":
    unittest.main()
