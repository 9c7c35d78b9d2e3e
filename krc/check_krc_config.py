#!/usr/bin/python3
"""The KRC side (krc/TactileServo.src, krc/dlrrc.ini) against the RT PC's FRI
bridge parameters (components/fri_bridge/params/fri.yaml) and protocol
(components/fri_bridge/include/tactile_fri/protocol.hpp).

usage: check_krc_config.py [--krc DIR] [--fri-yaml FILE] [--protocol FILE]

Checks, each a line "ok ..." or "MISMATCH ..." naming both files and keys:
  1. friOpen(ms) / 1000         == fri.cycle_time_s         (the KRC's cycle)
  2. $STIFFNESS.STRATEGY in force at friStart == 10 x ControlStrategy::CartImpedance
     (KRL's strategy codes 10/20/30 are the packet's robot.control 1/2/3 x 10)
  3. dlrrc.ini FRISOCK's port    == fri.udp.port             (where the KRC sends)
  4. dlrrc.ini FRIHOST is an IPv4 address (the RT PC's)
  5. $STIFFNESS.CPSTIFFNESS / CPDAMPING in force at friStart == fri.cart_stiffness /
     cart_damping (the arm behaves the same with or without fri.command_impedance)
and reports fri.udp.krc_port (the KRC's source port; 0 = any: set it only to a
port fri_check --monitor has shown).
Exit 0 when everything agrees, 1 on any mismatch or unreadable value (each
printed), 2 on usage errors. KRL is read without its comments (`;` to the
end of a line, outside strings) and case-insensitively.
"""
import argparse
import ipaddress
import os
import re
import sys

import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TOL = 1e-9  # numbers are compared as written (decimal text), so only float rounding


def strip_krl_comments(text):
    """KRL text without comments, one output line per input line (line numbers kept)."""
    out = []
    for line in text.splitlines():
        in_str, cut = False, len(line)
        for i, ch in enumerate(line):
            if ch == '"':
                in_str = not in_str
            elif ch == ";" and not in_str:
                cut = i
                break
        out.append(line[:cut])
    return out


def parse_src(path, failures):
    """friOpen cycle (ms), the strategy / stiffness / damping last assigned before
    friStart, with their line numbers. Each missing item is a failure."""
    lines = strip_krl_comments(open(path, encoding="latin-1").read())
    found = {"friopen": [], "fristart": [], "strategy": [], "cpstiffness": [], "cpdamping": []}
    num = r"([-+]?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?)"
    agg = r"\{\s*X\s+%s\s*,\s*Y\s+%s\s*,\s*Z\s+%s\s*,\s*A\s+%s\s*,\s*B\s+%s\s*,\s*C\s+%s\s*\}" % ((num,) * 6)
    for i, line in enumerate(lines):
        for m in re.finditer(r"\bfriOpen\s*\(\s*([^)]*)\)", line, re.I):
            found["friopen"].append((i + 1, m.group(1).strip()))
        for m in re.finditer(r"\bfriStart\s*\(", line, re.I):
            found["fristart"].append((i + 1, None))
        for m in re.finditer(r"\$STIFFNESS\.STRATEGY\s*=\s*(\S+)", line, re.I):
            found["strategy"].append((i + 1, m.group(1)))
        for key in ("cpstiffness", "cpdamping"):
            m = re.search(r"\$STIFFNESS\.%s\s*=\s*(.*)$" % key, line, re.I)
            if m:
                a = re.match(agg, m.group(1).strip(), re.I)
                found[key].append((i + 1, [float(x) for x in a.groups()] if a else m.group(1).strip()))
    res = {}
    if len(found["friopen"]) != 1:
        failures.append(f"{path}: expected exactly one friOpen(...) call, found {len(found['friopen'])}")
    else:
        ln, arg = found["friopen"][0]
        if re.fullmatch(r"\d+", arg):
            res["cycle_ms"] = (ln, int(arg))
        else:
            failures.append(f"{path}:{ln}: friOpen({arg}): the cycle must be a literal integer (ms)")
    if len(found["fristart"]) != 1:
        failures.append(f"{path}: expected exactly one friStart(...) call, found {len(found['fristart'])}")
        return res
    start_line = found["fristart"][0][0]
    for key in ("strategy", "cpstiffness", "cpdamping"):
        before = [x for x in found[key] if x[0] < start_line]
        if not before:
            failures.append(f"{path}: no $STIFFNESS.{key.upper()} assignment before friStart (line {start_line})")
            continue
        ln, val = before[-1]
        if key == "strategy":
            if re.fullmatch(r"\d+", val):
                res[key] = (ln, int(val))
            else:
                failures.append(f"{path}:{ln}: $STIFFNESS.STRATEGY = {val}: must be a literal integer")
        elif isinstance(val, list):
            res[key] = (ln, val)
        else:
            failures.append(f"{path}:{ln}: $STIFFNESS.{key.upper()} = {val}: expected {{X .., Y .., Z .., A .., B .., C ..}}")
    return res


def parse_ini(path, failures):
    """FRIHOST and FRISOCK of the [DLRRC] section."""
    section, res = None, {}
    for i, raw in enumerate(open(path, encoding="latin-1").read().splitlines()):
        line = raw.split(";", 1)[0].strip()
        if not line:
            continue
        m = re.fullmatch(r"\[(.*)\]", line)
        if m:
            section = m.group(1).strip().upper()
            continue
        if section != "DLRRC" or "=" not in line:
            continue
        k, v = (s.strip() for s in line.split("=", 1))
        res[k.upper()] = (i + 1, v)
    out = {}
    if "FRIHOST" not in res:
        failures.append(f"{path}: no FRIHOST in [DLRRC]")
    else:
        ln, v = res["FRIHOST"]
        try:
            out["host"] = (ln, str(ipaddress.IPv4Address(v)))
        except ValueError:
            failures.append(f"{path}:{ln}: FRIHOST={v}: not an IPv4 address (the RT PC's)")
    if "FRISOCK" not in res:
        failures.append(f"{path}: no FRISOCK in [DLRRC]")
    else:
        ln, v = res["FRISOCK"]
        m = re.fullmatch(r"(\d+)\s*(?:,\s*(\d+))?", v)
        if not m or not 1 <= int(m.group(1)) <= 65535:
            failures.append(f"{path}:{ln}: FRISOCK={v}: expected PORT,N with PORT in [1, 65535]")
        else:
            out["port"] = (ln, int(m.group(1)))
    return out


def cart_impedance_code(path, failures):
    m = re.search(r"enum\s+class\s+ControlStrategy\b[^{]*\{([^}]*)\}", open(path).read())
    c = re.search(r"\bCartImpedance\s*=\s*(\d+)", m.group(1)) if m else None
    if not c:
        failures.append(f"{path}: no ControlStrategy::CartImpedance value")
        return None
    return int(c.group(1))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--krc", default=os.path.join(ROOT, "krc"), help="folder with TactileServo.src and dlrrc.ini")
    ap.add_argument("--fri-yaml", default=os.path.join(ROOT, "components/fri_bridge/params/fri.yaml"))
    ap.add_argument("--protocol", default=os.path.join(ROOT, "components/fri_bridge/include/tactile_fri/protocol.hpp"))
    a = ap.parse_args()
    # paths as given, relative to the working directory when inside it (messages)
    rel = lambda p: os.path.relpath(p) if not os.path.relpath(p).startswith("..") else p
    a.fri_yaml, a.protocol = rel(a.fri_yaml), rel(a.protocol)
    src, ini = rel(os.path.join(a.krc, "TactileServo.src")), rel(os.path.join(a.krc, "dlrrc.ini"))
    failures, oks = [], []

    def compare(ok, what):
        (oks if ok else failures).append(what)

    krl = parse_src(src, failures)
    dl = parse_ini(ini, failures)
    code = cart_impedance_code(a.protocol, failures)
    fri = (yaml.safe_load(open(a.fri_yaml)) or {}).get("fri") or {}
    udp = fri.get("udp") or {}

    def fri_value(key, d=fri, prefix="fri."):
        if key not in d:
            failures.append(f"{a.fri_yaml}: no {prefix}{key}")
            return None
        return d[key]

    cycle = fri_value("cycle_time_s")
    if "cycle_ms" in krl and cycle is not None:
        ln, ms = krl["cycle_ms"]
        compare(abs(ms / 1000.0 - float(cycle)) <= TOL,
                f"cycle: {src}:{ln} friOpen({ms}) = {ms / 1000.0:g} s, {a.fri_yaml} fri.cycle_time_s = {cycle:g} s")
    if "strategy" in krl and code is not None:
        ln, st = krl["strategy"]
        compare(st == 10 * code,
                f"control strategy: {src}:{ln} $STIFFNESS.STRATEGY = {st} at friStart, the bridge follows only "
                f"Cartesian impedance: {a.protocol} ControlStrategy::CartImpedance = {code} (KRL {10 * code})")
    port = fri_value("port", udp, "fri.udp.")
    if "port" in dl and port is not None:
        ln, p = dl["port"]
        compare(p == int(port), f"port: {ini}:{ln} FRISOCK port {p}, {a.fri_yaml} fri.udp.port = {port}")
    if "host" in dl:
        oks.append(f"RT PC address: {ini}:{dl['host'][0]} FRIHOST={dl['host'][1]} (adapt to the RT PC's own)")
    for key, fkey in (("cpstiffness", "cart_stiffness"), ("cpdamping", "cart_damping")):
        v = fri_value(fkey)
        if key in krl and v is not None:
            ln, k = krl[key]
            same = len(v) == 6 and all(abs(float(x) - y) <= TOL * max(1.0, abs(y)) for x, y in zip(v, k))
            compare(same, f"{fkey}: {src}:{ln} $STIFFNESS.{key.upper()} = {k}, {a.fri_yaml} fri.{fkey} = {v}")
    kp = udp.get("krc_port", 0)
    oks.append(f"fri.udp.krc_port = {kp} ({'any source port' if not kp else 'only this source port'}; "
               "dlrrc.ini does not say which port the KRC sends from: take it from fri_check --monitor)")

    for o in oks:
        print("ok       " + o)
    for f in failures:
        print("MISMATCH " + f)
    print(f"check_krc_config: {len(oks)} ok, {len(failures)} mismatches")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
