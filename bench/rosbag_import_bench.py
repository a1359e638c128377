#!/usr/bin/env python3
"""Import throughput of `anchordb import rosbag` beside `anchordb import tum` on the same frames (issue 32,
acceptance 4). A figure, not a test.

Writes N depth frames of 640 x 480 (TUM Freiburg 1 intrinsics) of the room of tests/integration/ros_bags.py, the
camera holding still at place A (8 Hz stamps, one exact ray-cast image, seeded 2 mm noise per frame), twice: as a
ROS 1 bag in the TUM layout (32FC1 metres, /tf) and as a TUM RGB-D directory (16-bit PNG, 5000 units/m, depth.txt,
groundtruth.txt). Imports each into its own database with the given binary and prints frames per second of the
whole command (reading, converting and storing) and of the frames stored. The two importers store differently: the
rosbag import feeds one scene model from the frames after the observation rule's 1 s dwell, the TUM import makes one
scene model per frame; the figures are printed side by side, not as a ratio of equal work.

Usage (Debian's Python: python3-rosbag, genpy, genmsg):
  /usr/bin/python3 bench/rosbag_import_bench.py --anchordb build/server/anchordb [--frames 40] [--seed 7]
"""

import argparse
import json
import os
import random
import shutil
import struct
import subprocess
import sys
import tempfile
import time
import zlib

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "integration"))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "clients", "python"))
import anchordb_client  # noqa: E402
import genpy  # noqa: E402
import rosbag  # noqa: E402
import ros_bags  # noqa: E402

FR1 = (640, 480, 517.3, 516.5, 318.6, 255.3)
TUM_UNITS_PER_M = 5000


def png16(width, height, values):
    """A 16-bit greyscale PNG (big-endian samples, filter 0 on every row)."""
    rows = b"".join(b"\0" + struct.pack(">%dH" % width, *values[r * width:(r + 1) * width]) for r in range(height))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff)
    header = struct.pack(">IIBBBBB", width, height, 16, 0, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(rows, 6)) + chunk(b"IEND", b"")


def frames(n, seed):
    """[(stamp s, depth m list)]: the still camera at place A."""
    pose = ros_bags.optical_in_map(ros_bags.PLACE_A)
    exact = ros_bags.depth_metres(pose, random.Random(seed), noise_m=0.0, camera=FR1)
    rng = random.Random(seed + 1)
    return pose, [(ros_bags.T0_S + k / ros_bags.HZ, [d + rng.gauss(0, 0.002) for d in exact]) for k in range(n)]


def write_bag(path, pose, shots):
    classes = ros_bags.message_classes()
    frames_ = ros_bags.TUM["frames"]
    with rosbag.Bag(path, "w") as bag:
        w = ros_bags.Writer(bag, classes, camera=FR1)
        for stamp_s, depth in shots:
            stamp = genpy.Time.from_sec(stamp_s)
            w.tf("/tf", stamp, [w.transform(stamp, frames_[0], frames_[4], pose)])
            w.info(ros_bags.TUM["info"], stamp, frames_[4])
            w.image(ros_bags.TUM["depth"], stamp, frames_[4], "32FC1", depth)


def write_tum(folder, pose, shots):
    os.makedirs(os.path.join(folder, "depth"))
    q = ros_bags.quaternion(pose[0])
    with open(os.path.join(folder, "depth.txt"), "w") as d, open(os.path.join(folder, "rgb.txt"), "w") as rgb, \
            open(os.path.join(folder, "groundtruth.txt"), "w") as truth:
        for stamp_s, depth in shots:
            name = "depth/%.6f.png" % stamp_s
            units = [0 if i % FR1[0] == 0 else min(65535, round(v * TUM_UNITS_PER_M)) for i, v in enumerate(depth)]
            with open(os.path.join(folder, name), "wb") as f:
                f.write(png16(FR1[0], FR1[1], units))
            d.write("%.6f %s\n" % (stamp_s, name))
            rgb.write("%.6f rgb/%.6f.png\n" % (stamp_s, stamp_s))
            truth.write("%.6f %r %r %r %r %r %r %r\n" % ((stamp_s + 0.004,) + tuple(pose[1]) + tuple(q)))


def fresh_db(binary, folder):
    """A database with map `home` (created through a short-lived server)."""
    db = os.path.join(folder, "bench.sqlite")
    server = subprocess.Popen([binary, "serve", "--db", db, "--port", "0"], stdout=subprocess.PIPE,
                              stderr=subprocess.DEVNULL, text=True)
    try:
        url = server.stdout.readline().split("listening on ")[1].split()[0]
        anchordb_client.Client(url).create_map("home")
    finally:
        server.terminate()
        server.wait()
    return db


def timed(args):
    start = time.monotonic()
    run = subprocess.run(args, capture_output=True, text=True)
    seconds = time.monotonic() - start
    if run.returncode != 0:
        raise SystemExit("failed: %s\n%s" % (" ".join(args), run.stderr))
    return seconds, json.loads(run.stdout.strip().splitlines()[-1])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--anchordb", required=True)
    parser.add_argument("--frames", type=int, default=40)
    parser.add_argument("--seed", type=int, default=7)
    a = parser.parse_args()
    work = tempfile.mkdtemp(prefix="anchordb-rosbag-bench-")
    try:
        pose, shots = frames(a.frames, a.seed)
        bag = os.path.join(work, "tum.bag")
        write_bag(bag, pose, shots)
        write_tum(os.path.join(work, "tum"), pose, shots)
        os.makedirs(os.path.join(work, "db_bag"))
        os.makedirs(os.path.join(work, "db_tum"))
        db_bag, db_tum = fresh_db(a.anchordb, os.path.join(work, "db_bag")), fresh_db(a.anchordb, os.path.join(work, "db_tum"))
        bag_s, bag_summary = timed([a.anchordb, "import", "rosbag", "--db", db_bag, "--map", "home", "--bag", bag,
                                    "--preset", "tum"])
        tum_s, tum_summary = timed([a.anchordb, "import", "tum", "--db", db_tum, "--map", "home", "--dir",
                                    os.path.join(work, "tum")])
        used, imported = bag_summary["frames_used"], tum_summary["frames_imported"]
        print("%d frames 640 x 480 (seed %d), one process each, wall clock of the whole command:" % (a.frames, a.seed))
        print("  import rosbag --preset tum  %6.2f s  %6.1f frames/s read  (%d stored in %d scene model(s): %.1f/s)" % (
            bag_s, a.frames / bag_s, used, len(bag_summary["scenes"]), used / bag_s))
        print("  import tum                  %6.2f s  %6.1f frames/s read  (%d stored, one scene model each: %.1f/s)" % (
            tum_s, a.frames / tum_s, imported, imported / tum_s))
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
