"""`anchordb import rosbag` with the real binary on ROS 1 bags written here (ros_bags.py: a room with a table and a
cabinet; the camera holds still at place A in front of the table, drives to place B, holds still there, drives back
to A and holds still again; a key box appears on the table while the camera is away; seeded noise on depth and poses).

Checks the summary (frames read, used and skipped and why, scene models opened, the change events), what the database
then answers over HTTP (three scene models, posed at the camera's optical frame, with their frames; the first model
at A superseded by the second visit's, which merged it; the scene's cloud on the room's surfaces within 2 cm, which a
unit or frame mix-up would move, and a depth scale 1 % off too: checked failing; exactly one change event, the key
box added meanwhile, its segment inside the box), the optional inputs (a person mask topic: every stored frame's
dynamic input, the server's dynamic pixel count equal to the person's rendered pixels; an OccupancyGrid topic: the
occupancy layer holding the grid's trinary image), the TUM layout with `--preset tum` alone, and that bad bags (a
missing topic, an unknown encoding, no tf, a truncated file) fail with a clear message and a non-zero exit, leaving
the database file byte for byte as it was.

Needs Debian's ROS 1 Python packages (python3-rosbag, genpy, genmsg), numpy and the ROS -dev packages' .msg files:
ctest registers it (label `ros`) only when CMake found the ROS packages, and runs it with Debian's /usr/bin/python3.
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
# its first frame and a model opens after 1.0 s (frame 8), taking frames 8..23 (16); each drive's first frame is
# more than 0.15 m from where the model opened (left) and none of its 11 frames is still; at B, and at A again,
# stillness needs 0.5 s of poses there (from the 5th frame) and 1.0 s more, so the model opens at the 13th frame and
# takes the last 12. The 2 early images have no tf.
FRAMES_READ = ros_bags.EARLY + ros_bags.FRAMES_WITH_POSE  # 96
MODELS = [(ros_bags.PLACE_A, 16), (ros_bags.PLACE_B, 12), (ros_bags.PLACE_A, 12)]  # (place, frames) in stamp order
FRAMES_USED = sum(frames for _, frames in MODELS)
SKIPPED_MOVING = 8 + (ros_bags.DRIVE - 1) + 12 + (ros_bags.DRIVE - 1) + 12


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


def person_pixels_stored(seed):
    """The person's rendered pixels (the mask's nonzero pixels with a depth reading: not the first column) summed over
    the frames the models take (the last ones of each stay), which the server counts as dynamic."""
    poses = ros_bags.trajectory(seed)
    total = 0
    for (first, count, _), (_, frames) in zip(ros_bags.stays(), MODELS):
        for k in range(first + count - frames, first + count):
            boxes = ros_bags.scene_at(k)
            if ros_bags.PERSON in boxes:
                _, which = ros_bags.render(ros_bags.optical_in_map(poses[k][1]), boxes)
                person = which.reshape(ros_bags.HEIGHT, ros_bags.WIDTH) == boxes.index(ros_bags.PERSON)
                total += int(person[:, 1:].sum())
    return total


def inside(point, box, margin_m):
    lo, hi = box
    return all(lo[a] - margin_m <= point[a] <= hi[a] + margin_m for a in range(3))


class RosbagImportTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="anchordb-rosbag-")
        cls.robot_bag = os.path.join(cls.dir, "robot.bag")
        cls.robot_poses = ros_bags.write_bag(cls.robot_bag, ros_bags.ROBOT, SEED, with_mask=True, with_grid=True)
        cls.tum_bag = os.path.join(cls.dir, "tum.bag")
        ros_bags.write_bag(cls.tum_bag, ros_bags.TUM, SEED + 1)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def setUp(self):
        self.server = harness.Server(self, extra_args=ros_bags.SERVER_SETTINGS)
        self.server.client.create_map("home")
        self.server.stop()

    def import_bag(self, bag, *extra):
        return harness.run_cli(["import", "rosbag", "--db", self.server.db_path, "--map", "home", "--bag", bag] +
                               list(extra) + ros_bags.SERVER_SETTINGS, timeout=300)

    def expect_summary(self, run):
        self.assertEqual(run.returncode, 0, run.stdout + run.stderr)
        self.assertIn("frame %d/%d " % (FRAMES_USED, FRAMES_USED), run.stdout)  # the progress line
        s = summary_of(run.stdout)
        self.assertEqual(s["frames_read"], FRAMES_READ)
        self.assertEqual(s["frames_used"], FRAMES_USED)
        self.assertEqual(s["skipped_no_pose"], ros_bags.EARLY)
        self.assertEqual(s["skipped_moving"], SKIPPED_MOVING)
        self.assertEqual(s["skipped_every"], 0)
        self.assertEqual(s["skipped_stamp"], 0)
        self.assertEqual(len(s["scenes"]), len(MODELS), s)
        self.assertEqual(s["analyses"], 2 * len(MODELS))  # a begin and an end keyframe each
        self.assertEqual(s["analyses_not_done"], 0)
        self.assertEqual([(e["type"], e["detection"]) for e in s["events"]], [("added", "meanwhile")], s)
        return s

    def expect_places(self, scene_ids):
        """The models in stamp order, posed at the optical frame where they opened, with their frames; the first at A
        superseded by the second at A, which merged it."""
        c = self.server.start()
        self.assertEqual(len(c.request("GET", "/v1/maps/home/scenes")["scenes"]), len(MODELS))
        for k, ((place, frames), scene_id) in enumerate(zip(MODELS, scene_ids)):
            r, centre = ros_bags.optical_in_map(place)
            near = c.request("GET", "/v1/maps/home/scenes?near=%.4f,%.4f,%.4f&radius=0.05" % tuple(centre))["scenes"]
            self.assertIn(scene_id, [n["id"] for n in near])
            whole = c.request("GET", "/v1/maps/home/scenes/%d" % scene_id)
            self.assertEqual(whole["frames"], frames)
            self.assertEqual(whole["persisted_frames"], frames)
            if k == 0:
                self.assertEqual((whole["status"], whole["superseded_by"]), ("superseded", scene_ids[2]))
            else:
                self.assertEqual(whole["status"], "closed")
            if k == 2:
                self.assertEqual([m["scene"] for m in whole["merge"]["models_used"] if m["premises"]["merged"]],
                                 [scene_ids[0]])
            qx, qy, qz, qw = whole["pose"]["orientation"]
            ex, ey, ez, ew = ros_bags.quaternion(r)
            angle = 2 * math.acos(min(1.0, abs(qx * ex + qy * ey + qz * ez + qw * ew)))
            self.assertLess(angle, 0.02, whole["pose"])  # jitter is 1 mrad; a frame mix-up is 90 degrees off
        return c

    def expect_key_added(self, c, summary):
        """The one change event: the key box added meanwhile (the second visit's begin keyframe against the merged
        background of the first), its instance at the segment's centroid, inside the box."""
        events = c.request("GET", "/v1/maps/home/events")["events"]
        self.assertEqual([e["id"] for e in events], [e["id"] for e in summary["events"]])
        (e,) = events
        self.assertEqual((e["type"], e["detection"], e["scene"]), ("added", "meanwhile", summary["scenes"][2]))
        centroid = e["details"]["segment"]["centroid_m"]
        self.assertTrue(inside(centroid, ros_bags.KEY, 0.01), centroid)
        instance = c.request("GET", "/v1/maps/home/instances/%d" % e["instance"])
        self.assertLess(math.dist(instance["position_m"], centroid), 1e-6, instance)
        self.assertEqual(instance["status"], "present")

    def expect_cloud_on_surfaces(self, c, scene_id):
        data = c.request("GET", "/v1/maps/home/scenes/%d/cloud?format=pcd_ascii&frame=map" % scene_id)
        points = pcd_points(data)
        self.assertGreater(len(points), 1000)
        near = sum(1 for p in points if ros_bags.surface_distance(p) < 0.02)
        self.assertGreater(near / len(points), 0.95,
                           "%d of %d points within 2 cm of the room's surfaces" % (near, len(points)))

    def test_robot_layout_two_visits_mask_and_grid(self):
        run = self.import_bag(self.robot_bag, "--mask-topic", ros_bags.MASK_TOPIC, "--grid-topic", ros_bags.GRID_TOPIC)
        s = self.expect_summary(run)
        self.assertEqual(s["frames_masked"], FRAMES_USED)  # one mask per depth image in the bag
        self.assertEqual(s["dynamic_pixels"], person_pixels_stored(SEED))
        self.assertTrue(s["grid_imported"])
        c = self.expect_places(s["scenes"])
        self.expect_key_added(c, s)
        for scene_id in s["scenes"]:
            self.expect_cloud_on_surfaces(c, scene_id)
        # The grid as the occupancy layer: map_server's trinary image of its cells, top row = largest y.
        width, height, cells = ros_bags.occupancy_cells()
        self.assertEqual(c.request("GET", "/v1/maps/home/layers/occupancy?format=pgm"),
                         ros_bags.trinary_pgm(width, height, cells))

    def test_robot_layout_without_the_optional_topics(self):
        run = self.import_bag(self.robot_bag)
        s = self.expect_summary(run)
        self.assertEqual((s["frames_masked"], s["dynamic_pixels"], s["grid_imported"]), (0, 0, False))

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
        with self.subTest("mask topic not in the bag"):
            self.expect_refused(self.robot_bag, "no mask topic /camera/mask", "--mask-topic", "/camera/mask")
        with self.subTest("mask topic holding depth images"):
            self.expect_refused(self.robot_bag, "mask encoding '16UC1'", "--mask-topic", ros_bags.ROBOT["depth"])
        c = self.server.start()
        self.assertEqual(c.request("GET", "/v1/maps/home/scenes")["scenes"], [])


if __name__ == "__main__":
    unittest.main()
