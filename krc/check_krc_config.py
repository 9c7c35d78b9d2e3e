#!/usr/bin/python3
"""The KRC side (krc/TactileServo.src, .dat, krc/dlrrc.ini) against the RT PC's
FRI bridge parameters (params/sensors/fri.yaml) and protocol
(core/fri/include/tactile_fri/protocol.hpp, bridge.hpp), the
sensor's parameter file (params/sensors/wts0614.yaml: the pad's
load) and the first day's servo program (params/programs/first_touch.yaml).

usage: check_krc_config.py [--krc DIR] [--fri-yaml FILE] [--protocol FILE] [--bridge FILE]
                           [--sensor-params FILE] [--program FILE]

Checks, each a line "ok ..." or "MISMATCH ..." naming both files and keys:
  1. friOpen(ms) / 1000         == fri.cycle_time_s         (the KRC's cycle)
  2. $STIFFNESS.STRATEGY in force at friStart == 10 x ControlStrategy::CartImpedance
     (KRL's strategy codes 10/20/30 are the packet's robot.control 1/2/3 x 10)
  3. dlrrc.ini FRISOCK's port    == fri.udp.port             (where the KRC sends)
  4. dlrrc.ini FRIHOST is an IPv4 address (the RT PC's)
  5. $STIFFNESS.CPSTIFFNESS / CPDAMPING in force at friStart == fri.cart_stiffness /
     cart_damping (the arm behaves the same with or without fri.command_impedance)
  6. every field of $STIFFNESS written before friStart (nothing inherited from an
     earlier program); FRAMETYPE == fri.wrench_frame (#BASE: base, #TOOL: tool;
     the axes of estExtTcpFT, $STIFFNESS.TASKFRAME, that the bridge reads), BASE
     and TOOL $NULLFRAME, and $TOOL, $BASE $NULLFRAME: msrCartPos in the base
     frame {g} and at the flange, as the bridge and the servo read them
  7. MAXFORCE Z above the first day's program's safety.force_ceiling (the servo's
     named stop acts before the KRC caps the force) and CPMAXDELTA x, y, z (mm)
     beyond MAXFORCE / CPSTIFFNESS (the force cap acts before the deviation stop)
  8. $LOAD = the .dat's LOAD before friOpen, its M (kg) and CM X, Y, Z (mm) ==
     the sensor file's pad.pad_mass_kg and pad.pad_com_m (m)
  9. TS_START (.dat) in KUKA's E6AXIS order A1..A6, E1, with A3 and A5 bent
     (|angle| >= 5 deg: not the stretched-elbow / wrist singularity)
 10. after the command loop: PTP $AXIS_ACT_MES (the commanded pose brought to the
     measured one) before friStop and before the strategy goes back to 10
 11. the KRL exchange codes of the .dat (TS_REQ_STOP, TS_ST_*) == bridge.hpp's
     krl::kRequestStop, krl::kProgram* (the request the bridge sends, the steps
     it reads)
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


STIFFNESS_FIELDS = ("STRATEGY", "FRAMETYPE", "TOOL", "BASE", "CPSTIFFNESS", "CPDAMPING", "MAXFORCE",
                    "CPMAXDELTA", "AXISSTIFFNESS", "AXISDAMPING", "AXISMAXDELTA", "AXISMAXDELTATRQ")
NUM = r"([-+]?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?)"


def krl_aggregate(text):
    """{K v, K v, ...} (one level, numbers) -> [(key, value)] in written order, or None."""
    m = re.fullmatch(r"\s*\{(.*)\}\s*", text)
    if not m:
        return None
    out = []
    for item in m.group(1).split(","):
        kv = re.fullmatch(r"\s*(\w+)\s+" + NUM + r"\s*", item)
        if not kv:
            return None
        out.append((kv.group(1).upper(), float(kv.group(2))))
    return out


def parse_src_more(path, failures):
    """The $STIFFNESS fields, $TOOL/$BASE/$LOAD and the end sequence, with line numbers."""
    lines = strip_krl_comments(open(path, encoding="latin-1").read())
    res = {"stiff": {f: [] for f in STIFFNESS_FIELDS}, "tool": [], "base": [], "load": [], "ptp_msr": [],
           "fristart": [], "fristop": [], "friopen": []}
    for i, line in enumerate(lines):
        ln = i + 1
        m = re.search(r"\$STIFFNESS\.(\w+)\s*=\s*(.*)$", line, re.I)
        if m and m.group(1).upper() in res["stiff"]:
            res["stiff"][m.group(1).upper()].append((ln, m.group(2).strip()))
        for key, pat in (("tool", r"\$TOOL\s*=\s*(\S+)"), ("base", r"\$BASE\s*=\s*(\S+)"),
                         ("load", r"\$LOAD\s*=\s*(\S+)")):
            m = re.search(pat, line, re.I)
            if m:
                res[key].append((ln, m.group(1)))
        if re.search(r"\bPTP\s+\$AXIS_ACT_MES\b", line, re.I):
            res["ptp_msr"].append(ln)
        for key in ("friStart", "friStop", "friOpen"):
            if re.search(r"\b%s\s*\(" % key, line, re.I):
                res[key.lower()].append(ln)
    return res


def parse_dat(path, failures):
    """DECL LOAD name = {M .., CM {X .., ...}, J {..}} and DECL E6AXIS TS_START = {..}."""
    lines = strip_krl_comments(open(path, encoding="latin-1").read())
    res = {"loads": {}, "start": None}
    for i, line in enumerate(lines):
        m = re.search(r"\bDECL\s+LOAD\s+(\w+)\s*=\s*(\{.*\})", line, re.I)
        if m:
            mm = re.search(r"\bM\s+" + NUM, m.group(2), re.I)
            cm = re.search(r"\bCM\s*(\{[^}]*\})", m.group(2), re.I)
            agg = krl_aggregate(cm.group(1)) if cm else None
            if not mm or agg is None:
                failures.append(f"{path}:{i + 1}: LOAD {m.group(1)}: expected {{M kg, CM {{X mm, Y mm, Z mm, A, B, C}}, J {{..}}}}")
            else:
                res["loads"][m.group(1).upper()] = (i + 1, float(mm.group(1)), dict(agg))
        m = re.search(r"\bDECL\s+E6AXIS\s+TS_START\s*=\s*(\{.*\})", line, re.I)
        if m:
            agg = krl_aggregate(m.group(1))
            if agg is None:
                failures.append(f"{path}:{i + 1}: TS_START = {m.group(1)}: expected {{A1 deg, ..., A6 deg, E1 deg}}")
            else:
                res["start"] = (i + 1, agg)
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


def check_more(a, src, dat, krl, compare, oks, failures, fri):
    """Checks 6 to 10 (see the module's doc)."""
    more = parse_src_more(src, failures)
    d = parse_dat(dat, failures)
    start = more["fristart"][0] if len(more["fristart"]) == 1 else None
    if start is None:
        return
    before = lambda items: [x for x in items if x[0] < start]
    # 6. every $STIFFNESS field, and the frames the bridge and the servo read in
    fields = {}
    for f in STIFFNESS_FIELDS:
        b = before(more["stiff"][f])
        if not b:
            failures.append(f"{src}: $STIFFNESS.{f} is not written before friStart (line {start}): the KRC would "
                            "keep whatever an earlier program left there")
        else:
            fields[f] = b[-1]
    servo_reads = ("the servo reads estimated_wrench (estExtTcpFT, in $STIFFNESS.TASKFRAME) in the base frame {g} "
                   "and flange_pose (msrCartPos) at the flange: core/servo/include/tactile_servo/servo.hpp")
    frame = fri.get("wrench_frame")
    if frame not in ("base", "tool"):
        failures.append(f"{a.fri_yaml}: fri.wrench_frame = {frame}: expected base or tool (the axes the bridge reads "
                        "estExtTcpFT in)")
    elif "FRAMETYPE" in fields:
        ln, v = fields["FRAMETYPE"]
        compare(v.upper() == "#" + frame.upper(),
                f"task frame: {src}:{ln} $STIFFNESS.FRAMETYPE = {v} (the axes the KRC sends estExtTcpFT in), "
                f"{a.fri_yaml} fri.wrench_frame = {frame} (the axes the bridge reads it in; "
                f"#{frame.upper()} matches; fri_check --wrench-check tells the KRC's from a known weight)")
    for f, want in (("BASE", "$NULLFRAME"), ("TOOL", "$NULLFRAME")):
        if f in fields:
            ln, v = fields[f]
            compare(v.upper() == want, f"task frame: {src}:{ln} $STIFFNESS.{f} = {v}, expected {want}: {servo_reads}")
    for key, name in (("tool", "$TOOL"), ("base", "$BASE")):
        b = before(more[key])
        if not b:
            failures.append(f"{src}: no {name} assignment before friStart: {servo_reads}")
        else:
            ln, v = b[-1]
            compare(v.upper() == "$NULLFRAME", f"frames: {src}:{ln} {name} = {v}, expected $NULLFRAME: {servo_reads}")
    # 7. MAXFORCE against the program's force ceiling and CPMAXDELTA against MAXFORCE / stiffness
    agg = {}
    for f in ("MAXFORCE", "CPMAXDELTA"):
        if f in fields:
            v = krl_aggregate(fields[f][1])
            if v is None or [k for k, _ in v] != ["X", "Y", "Z", "A", "B", "C"]:
                failures.append(f"{src}:{fields[f][0]}: $STIFFNESS.{f} = {fields[f][1]}: expected {{X .., Y .., Z .., A .., B .., C ..}}")
            else:
                agg[f] = dict(v)
    prog = yaml.safe_load(open(a.program)) or {}
    ceiling = ((prog.get("safety") or {}).get("force_ceiling"))
    if ceiling is None:
        failures.append(f"{a.program}: no safety.force_ceiling")
    elif "MAXFORCE" in agg:
        mz = agg["MAXFORCE"]["Z"]
        compare(mz > float(ceiling), f"force cap: {src}:{fields['MAXFORCE'][0]} $STIFFNESS.MAXFORCE Z = {mz:g} N, "
                f"{a.program} safety.force_ceiling = {ceiling} N (the servo's named stop must act below the KRC's cap)")
    if "MAXFORCE" in agg and "CPMAXDELTA" in agg and "cpstiffness" in krl:
        ln_k, k = krl["cpstiffness"]
        spring = [1000.0 * agg["MAXFORCE"][ax] / k[i] for i, ax in enumerate("XYZ")]
        delta = [agg["CPMAXDELTA"][ax] for ax in "XYZ"]
        compare(all(dl > sp for dl, sp in zip(delta, spring)),
                f"deviation stop: {src}:{fields['CPMAXDELTA'][0]} $STIFFNESS.CPMAXDELTA X/Y/Z = {delta} mm, beyond "
                f"MAXFORCE / CPSTIFFNESS = {[round(x, 3) for x in spring]} mm ({src}:{fields['MAXFORCE'][0]}, {src}:{ln_k})")
    # 8. the pad's load: $LOAD = the .dat's LOAD, against the sensor file
    opened = more["friopen"][0] if more["friopen"] else start
    loads = [x for x in more["load"] if x[0] < opened]
    sensor = (yaml.safe_load(open(a.sensor_params)) or {}).get("pad") or {}
    if not loads:
        failures.append(f"{src}: no $LOAD assignment before friOpen (line {opened}): the pad's load is whatever "
                        f"the KRC had; set $LOAD = the .dat's LOAD (its values from {a.sensor_params} pad:)")
    elif "pad_mass_kg" not in sensor or "pad_com_m" not in sensor or len(sensor["pad_com_m"]) != 3:
        failures.append(f"{a.sensor_params}: no pad: pad_mass_kg, pad_com_m [x, y, z] (m)")
    else:
        ln, name = loads[-1]
        if name.upper() not in d["loads"]:
            failures.append(f"{src}:{ln}: $LOAD = {name}: no DECL LOAD {name} in {dat}")
        else:
            dln, m, cm = d["loads"][name.upper()]
            mass = float(sensor["pad_mass_kg"])
            compare(abs(m - mass) <= 1e-6, f"pad mass: {dat}:{dln} {name}.M = {m:g} kg, "
                    f"{a.sensor_params} pad.pad_mass_kg = {mass:g} kg")
            com = [1000.0 * float(x) for x in sensor["pad_com_m"]]
            got = [cm.get(ax) for ax in "XYZ"]
            compare(None not in got and all(abs(g - c) <= 1e-6 for g, c in zip(got, com)),
                    f"pad centre of mass: {dat}:{dln} {name}.CM X/Y/Z = {got} mm, {a.sensor_params} "
                    f"pad.pad_com_m = {sensor['pad_com_m']} m = {[round(c, 6) for c in com]} mm")
    # 9. TS_START: KUKA's order and a bent elbow and wrist
    if d["start"] is None:
        failures.append(f"{dat}: no DECL E6AXIS TS_START")
    else:
        ln, axes = d["start"]
        order = [k for k, _ in axes]
        compare(order == ["A1", "A2", "A3", "A4", "A5", "A6", "E1"],
                f"start pose order: {dat}:{ln} TS_START lists {order}, KUKA's E6AXIS order is A1..A6, E1")
        v = dict(axes)
        compare(abs(v.get("A3", 0.0)) >= 5.0 and abs(v.get("A5", 0.0)) >= 5.0,
                f"start pose: {dat}:{ln} TS_START A3 = {v.get('A3')} deg, A5 = {v.get('A5')} deg "
                "(|A3|, |A5| >= 5 deg: not the stretched elbow or wrist)")
    # 11. the KRL exchange codes
    text = "\n".join(strip_krl_comments(open(dat, encoding="latin-1").read()))
    hpp = open(a.bridge).read()
    for krl_name, cpp_name in (("TS_REQ_STOP", "kRequestStop"), ("TS_ST_INIT", "kProgramInit"),
                               ("TS_ST_MONITOR", "kProgramMonitor"), ("TS_ST_CONFIRM", "kProgramConfirm"),
                               ("TS_ST_COMMAND", "kProgramCommand"), ("TS_ST_STOPPING", "kProgramStopping"),
                               ("TS_ST_CLOSED", "kProgramClosed")):
        mk = re.search(r"\bDECL\s+INT\s+%s\s*=\s*(-?\d+)" % krl_name, text, re.I)
        mc = re.search(r"\b%s\s*=\s*(-?\d+)\s*;" % cpp_name, hpp)
        if not mk or not mc:
            failures.append(f"KRL exchange: {krl_name} in {dat} {'found' if mk else 'missing'}, "
                            f"krl::{cpp_name} in {a.bridge} {'found' if mc else 'missing'}")
            continue
        compare(int(mk.group(1)) == int(mc.group(1)),
                f"KRL exchange: {dat} {krl_name} = {mk.group(1)}, {a.bridge} krl::{cpp_name} = {mc.group(1)}")
    # 10. the end: PTP $AXIS_ACT_MES after the command loop, before friStop and strategy 10
    stops = [ln for ln in more["fristop"] if ln > start]
    back = [ln for ln, v in more["stiff"]["STRATEGY"] if ln > start]
    ptp = [ln for ln in more["ptp_msr"] if ln > start]
    first_after = min(stops + back) if (stops or back) else None
    compare(bool(ptp) and first_after is not None and ptp[0] < first_after,
            f"end of run: {src}: PTP $AXIS_ACT_MES after friStart (line {start}) at line "
            f"{ptp[0] if ptp else 'none'}, before friStop / the strategy change at line {first_after}: the "
            "commanded pose is the measured one before position control")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--krc", default=os.path.join(ROOT, "krc"), help="folder with TactileServo.src and dlrrc.ini")
    ap.add_argument("--fri-yaml", default=os.path.join(ROOT, "params/sensors/fri.yaml"))
    ap.add_argument("--protocol", default=os.path.join(ROOT, "core/fri/include/tactile_fri/protocol.hpp"))
    ap.add_argument("--bridge", default=os.path.join(ROOT, "core/fri/include/tactile_fri/bridge.hpp"))
    ap.add_argument("--sensor-params", default=os.path.join(ROOT, "params/sensors/wts0614.yaml"),
                    help="the sensor's parameter file with pad: pad_mass_kg, pad_com_m")
    ap.add_argument("--program", default=os.path.join(ROOT, "params/programs/first_touch.yaml"),
                    help="the first day's servo program (safety.force_ceiling)")
    a = ap.parse_args()
    # paths as given, relative to the working directory when inside it (messages)
    rel = lambda p: os.path.relpath(p) if not os.path.relpath(p).startswith("..") else p
    a.fri_yaml, a.protocol = rel(a.fri_yaml), rel(a.protocol)
    a.sensor_params, a.program, a.bridge = rel(a.sensor_params), rel(a.program), rel(a.bridge)
    src, ini = rel(os.path.join(a.krc, "TactileServo.src")), rel(os.path.join(a.krc, "dlrrc.ini"))
    dat = rel(os.path.join(a.krc, "TactileServo.dat"))
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
    check_more(a, src, dat, krl, compare, oks, failures, fri)
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
