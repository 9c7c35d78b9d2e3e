#!/usr/bin/python3
"""ctest ros_bag_replay: a bag recorded from the ROS streams of the simulated
edge exploration (tests/ros/run_ros_test.sh records /tactile/image and
/tactile/features with rosbag) replayed through the project's own feature code:
every image of the bag goes, in order, through tests/ros/replay_features (the
tactile::SensorStage of the deployment's FeatureComponent, configured from the
same sensor file), and the features it gives are compared, message by message,
with the /tactile/features message of the same frame (the same stamp).

usage: check_bag.py BAG REPLAY_TOOL SENSOR_YAML [--mutate-threshold FACTOR]

Checks (each printed; exit 1 when one fails):
  - the bag holds images and features, with contact frames among them;
  - every image has the features message of the same stamp, and the frames'
    sequence numbers have no gap (the extractor keeps history: every frame is
    needed, in order);
  - the bag starts with a frame in which no taxel fired and within the first
    FIRST_SEQ_MAX frames of the run, so the deployment's extractor and the
    replay's (reset) share their state there;
  - status, contact type, alpha_defined and area equal; every real field
    within REL_TOL relative (plus a per-unit absolute floor, ABS_TOL).

--mutate-threshold FACTOR: the replay runs with the sensor file's
contact_threshold and threshold multiplied by FACTOR (a deliberately wrong
feature configuration); the check then must find mismatches in the contact
frames, and exits 0 only if it does (ctest ros_bag_replay_detects).
"""
import os
import struct
import subprocess
import sys
import tempfile

import rosbag
import yaml

# The image is 32FC1: each taxel force rounded to float32 (relative error
# <= 2^-24 = 6e-8). The features computed from it differ from the
# deployment's (float64 frame) by about that: largest seen 5e-8 relative on
# forces and eigenvalues, 3e-10 m on a CoP near zero (ros/README.md); REL_TOL
# is 200x the former, the floors 3x the latter.
REL_TOL = 1e-5
# Absolute floors per unit, for values near zero (differences of nearly equal
# numbers: DZMP, a centred CoP): N, m, m^2, rad.
ABS_TOL = {"N": 1e-7, "m": 1e-9, "m2": 1e-13, "rad": 1e-6}
# alpha_z (Eq. B.5) is the angle of g = (mu20 - mu02, 2 mu11), |g| = lambda1 -
# lambda2. Rounding the image to float32 moves the central moments by about
# 1e-11 m^2 (6e-8 of x^2 over the pad, cancellation in E[x^2] - CoP^2): where
# the recorded gap lambda1 - lambda2 is below ALPHA_GAP_MIN (100x that) the
# angle and its `defined` flag are rounding noise in the deployment and in the
# replay alike (e.g. a contact on one taxel: lambda1 ~ 1e-20 m^2), so they are
# compared only where the gap is resolvable, and a held angle only when the
# frame it was held from was.
ALPHA_GAP_MIN = 1e-9  # m^2 (about 1e-4 pitch^2)
FIRST_SEQ_MAX = 70  # the first 0.5 s of frames at 140 Hz: the arm is still in free motion

REAL_FIELDS = [("force", "N"), ("cop_x", "m"), ("cop_y", "m"), ("coc_x", "m"), ("coc_y", "m"), ("dzmp_x", "m"),
               ("dzmp_y", "m"), ("alpha_z", "rad"), ("d_z", "m"), ("lambda1", "m2"), ("lambda2", "m2"),
               ("max_taxel", "N")]
EXACT_FIELDS = ["status", "contact", "alpha_defined", "area"]
REPLAY_COLUMNS = ["seq", "status", "contact", "alpha_defined", "area", "force", "cop_x", "cop_y", "coc_x", "coc_y",
                  "dzmp_x", "dzmp_y", "alpha_z", "d_z", "lambda1", "lambda2", "max_taxel"]

failures = []


def check(ok, what):
    print(("ok    " if ok else "FAIL  ") + what, flush=True)
    if not ok:
        failures.append(what)
    return ok


def image_forces(msg):
    if msg.encoding != "32FC1" or msg.is_bigendian or msg.step != 4 * msg.width:
        return None
    n = msg.width * msg.height
    return struct.unpack("<%df" % n, bytes(msg.data[:4 * n]))


def main():
    args = sys.argv[1:]
    mutate = None
    if "--mutate-threshold" in args:
        i = args.index("--mutate-threshold")
        mutate = float(args[i + 1])
        del args[i:i + 2]
    if len(args) != 3:
        print(__doc__)
        return 2
    bag_file, tool, sensor_yaml = args

    images, features = [], []
    with rosbag.Bag(bag_file) as bag:
        for topic, msg, _ in bag.read_messages(topics=["/tactile/image", "/tactile/features"]):
            (images if topic == "/tactile/image" else features).append(msg)
    print("bag %s: %d images, %d features messages" % (bag_file, len(images), len(features)))
    check(len(images) > 100 and len(features) > 100, "the bag holds images and features (> 100 each)")
    by_stamp = {m.header.stamp.to_nsec(): m for m in features}
    check(len(by_stamp) == len(features), "one features message per stamp")
    images.sort(key=lambda m: m.header.stamp.to_nsec())
    # The two topics' subscriptions connect at slightly different times, and the
    # deployer's end cuts them at slightly different times: the frames compared
    # run from the first to the last image with its features message, and
    # every image in between must have it.
    matched = [i for i, im in enumerate(images) if im.header.stamp.to_nsec() in by_stamp]
    if not check(len(matched) > 0, "images with the features message of their stamp"):
        return 1
    inner = images[matched[0]:matched[-1] + 1]
    pairs = [(im, by_stamp.get(im.header.stamp.to_nsec())) for im in inner]
    missing = [im.header.stamp for im, f in pairs if f is None]
    check(not missing, "every image from the first to the last matched one has the features message of its stamp "
          "(%d frames; %d images before, %d after)%s" % (len(pairs), matched[0], len(images) - 1 - matched[-1],
                                                         "" if not missing else ": missing at %s" % missing[:5]))
    if missing:
        return 1
    seqs = [f.seq for _, f in pairs]
    gaps = [(a, b) for a, b in zip(seqs, seqs[1:]) if b != a + 1]
    check(not gaps, "frame sequence numbers %d..%d without a gap%s" %
          (seqs[0], seqs[-1], "" if not gaps else " (gaps: %s)" % gaps[:5]))
    first = pairs[0][1]
    check(first.max_taxel == 0.0 and first.contact == 0,
          "the first recorded frame (seq %d) has no taxel firing: the deployment's extractor is in its reset state"
          % first.seq)
    check(first.seq <= FIRST_SEQ_MAX, "the bag starts within the first %d frames of the run (seq %d)"
          % (FIRST_SEQ_MAX, first.seq))
    contact_frames = sum(1 for _, f in pairs if f.contact != 0)
    check(contact_frames > 50, "the bag has contact frames (%d)" % contact_frames)

    t0 = pairs[0][0].header.stamp
    tmp = tempfile.mkdtemp(prefix="tactile-bag-")
    frames_file = os.path.join(tmp, "frames.txt")
    with open(frames_file, "w") as out:
        for im, f in pairs:
            forces = image_forces(im)
            if forces is None:
                check(False, "image seq %d is 32FC1, little-endian, dense" % f.seq)
                return 1
            t = (im.header.stamp - t0).to_sec()
            out.write("%d %.9f %d %d %s\n" % (f.seq, t, im.height, im.width, " ".join("%.9g" % v for v in forces)))
    sensor = sensor_yaml
    if mutate is not None:
        doc = yaml.safe_load(open(sensor_yaml))
        feats = doc["features"]
        for key in ("contact_threshold", "threshold"):
            if isinstance(feats.get(key), (int, float)):
                feats[key] = feats[key] * mutate
        sensor = os.path.join(tmp, "sensor_mutated.yaml")
        yaml.safe_dump(doc, open(sensor, "w"))
        print("mutation: contact_threshold and threshold x %g (%s)" % (mutate, sensor))
    run = subprocess.run([tool, sensor, frames_file], capture_output=True, text=True)
    if not check(run.returncode == 0, "replay_features ran (exit %d) %s" % (run.returncode, run.stderr.strip())):
        return 1
    rows = [dict(zip(REPLAY_COLUMNS, line.split())) for line in run.stdout.splitlines()]
    check(len(rows) == len(pairs), "one replayed result per image (%d)" % len(rows))

    mismatches = []
    worst = {name: 0.0 for name, _ in REAL_FIELDS}
    alpha_comparable = True  # after reset both hold alpha_z = 0
    alpha_compared = alpha_skipped = 0
    for (im, f), r in zip(pairs, rows):
        bad = []
        if int(r["seq"]) != f.seq:
            bad.append("seq %s" % r["seq"])
        resolvable = f.lambda1 - f.lambda2 >= ALPHA_GAP_MIN
        if f.alpha_defined or int(r["alpha_defined"]):
            alpha_comparable = resolvable
        compare_alpha = alpha_comparable and (resolvable or not f.alpha_defined)
        if f.contact != 0:
            if compare_alpha:
                alpha_compared += 1
            else:
                alpha_skipped += 1
        for name in EXACT_FIELDS:
            if name == "alpha_defined" and not resolvable:
                continue
            got = int(r[name])
            want = int(getattr(f, name))
            if got != want:
                bad.append("%s %d (recorded %d)" % (name, got, want))
        for name, unit in REAL_FIELDS:
            if name == "alpha_z" and not compare_alpha:
                continue
            got = float(r[name])
            want = float(getattr(f, name))
            diff = abs(got - want)
            scale = max(abs(got), abs(want))
            if scale > 0:
                worst[name] = max(worst[name], diff / max(scale, ABS_TOL[unit] / REL_TOL))
            if diff > ABS_TOL[unit] + REL_TOL * scale:
                bad.append("%s %.9g (recorded %.9g)" % (name, got, want))
        if bad:
            mismatches.append((f.seq, f.contact, bad))
    print("contact frames with alpha_z compared: %d; not compared (gap below ALPHA_GAP_MIN, or held from such a frame): %d"
          % (alpha_compared, alpha_skipped))
    if mutate is None:
        check(alpha_compared > 50, "alpha_z compared on more than 50 contact frames (%d)" % alpha_compared)
    print("largest relative difference per field (over the scale or its floor): " +
          ", ".join("%s %.2g" % (k, v) for k, v in worst.items()))
    if mutate is None:
        for seq, _, bad in mismatches[:10]:
            print("  frame seq %d: %s" % (seq, "; ".join(bad)))
        check(not mismatches, "every replayed frame equals its recorded features (REL_TOL %g): %d of %d differ"
              % (REL_TOL, len(mismatches), len(pairs)))
    else:
        in_contact = [m for m in mismatches if m[1] != 0]
        for seq, _, bad in in_contact[:3]:
            print("  frame seq %d: %s" % (seq, "; ".join(bad)))
        check(len(in_contact) > 0, "the mutated replay differs from the recording (%d frames, %d in contact)"
              % (len(mismatches), len(in_contact)))
    print("check_bag: %s" % ("passed" if not failures else "%d check(s) failed" % len(failures)))
    return 0 if not failures else 1


if __name__ == "__main__":
    sys.exit(main())
