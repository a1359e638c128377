"""`anchordb import rosbag` with the real binary on ROS 1 bags written here (ros_bags.py: a room with a table and a
cabinet, the camera holding still at two places with a drive between them; seeded noise on depth and poses).

Checks the summary (frames read, used and skipped and why, scene models opened), what the database then answers over
HTTP (one closed scene model at each place, posed at the camera's optical frame, with its frames; the scene's cloud on
the room's surfaces within 2 cm, which a unit or frame mix-up would move, and a depth scale 1 % off too: checked
failing), the TUM layout with `--preset tum` alone, and that bad bags (a missing topic, an unknown encoding, no tf, a
truncated file) fail with a clear message and a non-zero exit, leaving the database file byte for byte as it was.

Needs Debian's ROS 1 Python packages (python3-rosbag, genpy, genmsg) and the ROS -dev packages' .msg files: ctest
registers it (label `ros`) only when CMake found the ROS packages, and runs it with Debian's /usr/bin/python3.
"""

import hashlib
import json
import math
import os
import shutil
import tempfile
import unittest

import harness
import ros_bags

SEED = 32
# What the observation rule makes of the trajectory (engine/observation defaults, 8 Hz): at A the camera is still from
# its first frame and a model opens after 1.0 s (frame 8), taking frames 8..23 (16); the drive's first frame is 0.25 m
# away (left, > 0.15 m) and none of its 11 frames is still; at B stillness needs 0.5 s of poses at B (from its 5th
# frame) and 1.0 s more, so the model opens at B's 13th frame and takes the last 12. The 2 early images have no tf.
FRAMES_READ = ros_bags.EARLY + ros_bags.HOLD_A + ros_bags.DRIVE - 1 + ros_bags.HOLD_B  # 61
USED_A, USED_B = 16, 12
SKIPPED_MOVING = 8 + (ros_bags.DRIVE - 1) + 12


def summary_of(stdout):
    """The summary JSON, the last line of the command's output."""
    return json.loads(stdout.strip().splitlines()[-1])


def file_digest(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def pcd_points(data):
    """x y z of an ASCII PCD."""
    lines = data.decode().splitlines()
    fields = next(l.split()[1:] for l in lines if l.startswith("FIELDS"))
    start = next(i for i, l in enumerate(lines) if l.startswith("DATA")) + 1
    ix, iy, iz = fields.index("x"), fields.index("y"), fields.index("z")
    return [(float(v[ix]), float(v[iy]), float(v[iz])) for v in (l.split() for l in lines[start:]) if v]


class RosbagImportTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="anchordb-rosbag-")
        cls.robot_bag = os.path.join(cls.dir, "robot.bag")
        cls.robot_poses = ros_bags.write_bag(cls.robot_bag, ros_bags.ROBOT, SEED)
        cls.tum_bag = os.path.join(cls.dir, "tum.bag")
        ros_bags.write_bag(cls.tum_bag, ros_bags.TUM, SEED + 1)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def setUp(self):
        self.server = harness.Server(self)
        self.server.client.create_map("home")
        self.server.stop()

    def import_bag(self, bag, *extra):
        return harness.run_cli(["import", "rosbag", "--db", self.server.db_path, "--map", "home", "--bag", bag] +
                               list(extra), timeout=300)

    def expect_summary(self, run):
        self.assertEqual(run.returncode, 0, run.stdout + run.stderr)
        self.assertIn("frame %d/%d " % (USED_A + USED_B, USED_A + USED_B), run.stdout)  # the progress line
        s = summary_of(run.stdout)
        self.assertEqual(s["frames_read"], FRAMES_READ)
        self.assertEqual(s["frames_used"], USED_A + USED_B)
        self.assertEqual(s["skipped_no_pose"], ros_bags.EARLY)
        self.assertEqual(s["skipped_moving"], SKIPPED_MOVING)
        self.assertEqual(s["skipped_every"], 0)
        self.assertEqual(s["skipped_stamp"], 0)
        self.assertEqual(len(s["scenes"]), 2, s)
        return s

    def scene_near(self, c, point):
        answer = c.request("GET", "/v1/maps/home/scenes?near=%.4f,%.4f,%.4f&radius=0.05" % tuple(point))
        self.assertEqual(len(answer["scenes"]), 1, answer)
        return answer["scenes"][0]

    def expect_places(self, scene_ids):
        """One closed model at each place, posed at the optical frame where it opened, with its frames."""
        c = self.server.start()
        self.assertEqual(len(c.request("GET", "/v1/maps/home/scenes")["scenes"]), 2)
        places = [(ros_bags.PLACE_A, USED_A), (ros_bags.PLACE_B, USED_B)]
        for (place, frames), scene_id in zip(places, scene_ids):
            r, centre = ros_bags.optical_in_map(place)
            scene = self.scene_near(c, centre)
            self.assertEqual(scene["id"], scene_id)
            self.assertEqual(scene["status"], "closed")
            whole = c.request("GET", "/v1/maps/home/scenes/%d" % scene_id)
            self.assertEqual(whole["frames"], frames)
            self.assertEqual(whole["persisted_frames"], frames)
            qx, qy, qz, qw = scene["pose"]["orientation"]
            ex, ey, ez, ew = ros_bags.quaternion(r)
            angle = 2 * math.acos(min(1.0, abs(qx * ex + qy * ey + qz * ez + qw * ew)))
            self.assertLess(angle, 0.02, scene["pose"])  # jitter is 1 mrad; a frame mix-up is 90 degrees off
        return c

    def expect_cloud_on_surfaces(self, c, scene_id):
        data = c.request("GET", "/v1/maps/home/scenes/%d/cloud?format=pcd_ascii&frame=map" % scene_id)
        points = pcd_points(data)
        self.assertGreater(len(points), 1000)
        near = sum(1 for p in points if ros_bags.surface_distance(p) < 0.02)
        self.assertGreater(near / len(points), 0.95,
                           "%d of %d points within 2 cm of the room's surfaces" % (near, len(points)))

    def test_robot_layout_two_places(self):
        run = self.import_bag(self.robot_bag)
        s = self.expect_summary(run)
        c = self.expect_places(s["scenes"])
        for scene_id in s["scenes"]:
            self.expect_cloud_on_surfaces(c, scene_id)

    def test_tum_layout_with_the_preset_alone(self):
        run = self.import_bag(self.tum_bag, "--preset", "tum")
        s = self.expect_summary(run)
        c = self.expect_places(s["scenes"])
        self.expect_cloud_on_surfaces(c, s["scenes"][0])  # 32FC1 metres (NaN: no reading) read as metres
        # Without the preset the robot layout's topics are looked for, and missed.
        self.server.stop()
        run = self.import_bag(self.tum_bag)
        self.assertNotEqual(run.returncode, 0)
        self.assertIn("no topic /camera/depth/image_rect_raw", run.stderr)

    def expect_refused(self, bag, message, *extra):
        before = file_digest(self.server.db_path)
        run = self.import_bag(bag, *extra)
        self.assertEqual(run.returncode, 2, run.stdout + run.stderr)
        self.assertIn(bag, run.stderr)
        self.assertIn(message, run.stderr)
        self.assertEqual(file_digest(self.server.db_path), before, "a refused bag changed the database")

    def test_bad_bags_fail_clearly_and_change_nothing(self):
        bad = os.path.join(self.dir, "bad")
        os.makedirs(bad, exist_ok=True)
        cases = [("no_info.bag", dict(with_info=False), "no topic /camera/depth/camera_info"),
                 ("bgr8.bag", dict(encoding="bgr8"), "encoding 'bgr8'"),
                 ("no_tf.bag", dict(with_tf=False), "no tf")]
        for name, options, message in cases:
            with self.subTest(name):
                path = os.path.join(bad, name)
                ros_bags.write_bag(path, ros_bags.ROBOT, SEED, **options)
                self.expect_refused(path, message)
        with self.subTest("truncated"):
            path = os.path.join(bad, "truncated.bag")
            with open(self.robot_bag, "rb") as f:
                whole = f.read()
            with open(path, "wb") as f:
                f.write(whole[:len(whole) * 2 // 3])  # a recording cut short: the index at the end is gone
            self.expect_refused(path, "truncated")
        with self.subTest("depth topic not in the bag"):
            self.expect_refused(self.robot_bag, "no topic /camera/depth/image", "--depth-topic", "/camera/depth/image")
        c = self.server.start()
        self.assertEqual(c.request("GET", "/v1/maps/home/scenes")["scenes"], [])


if __name__ == "__main__":
    unittest.main()
