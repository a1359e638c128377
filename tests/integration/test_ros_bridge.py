"""The anchordb_ros bridge node against a real rosmaster (free loopback port), a real anchordb server and `rosbag
play` of the bag of test_ros_rosbag_import.py (ros_bags.py: two visits to a table, a key box appearing on the second,
a person walking by during it with a person mask, the room's OccupancyGrid).

Checks, on the same bag, that the node and `anchordb import rosbag` give the same memory (issue 32, acceptance 1):
the same scene models (count, order, status and supersession, frames, first stamp, the models merged, pose within
1 mm / 1 mrad), the same change events (type, detection, scene, instance, label, segment points, centroid within 1 mm,
evidence keyframes), the same instances (position within 1 mm), the same dynamic input (frames sent with a mask, the
server's dynamic pixel count) and the same occupancy layer (byte for byte); the figures are printed for the note.
Also that the key's change event arrives on ~events as over HTTP; that ~where_is and ~label answer for the detected
key and the label's event and the markers follow; that a probability layer comes out as an OccupancyGrid; and that
an anchordb server stopped in the middle of the bag and started again crashes nothing, is reported on /rosout, and
loses no acknowledged frame (the frames the server holds are the frames the node counted as stored).

Needs Debian's ROS 1 (rosmaster, rosbag, rospy, genpy, genmsg), numpy and the anchordb_ros binary
($ANCHORDB_ROS_BIN): registered by ctest only when both were built (label `ros`).
"""

import json
import math
import os
import re
import shutil
import struct
import subprocess
import tempfile
import threading
import time
import unittest

import anchordb_client
import harness
import ros_bags
import ros_graph

SEED = 32
DEPTH, INFO = ros_bags.ROBOT["depth"], ros_bags.ROBOT["info"]
NODE = "/anchordb_ros"
POSITION_TOLERANCE_M = 1e-3   # scene poses, event centroids, instance positions: import vs bridge
ANGLE_TOLERANCE_RAD = 1e-3
MODEL_FRAMES = [16, 12, 12]   # the models at A, B, A again (test_ros_rosbag_import.MODELS)

_COUNTS = re.compile(
    r"offered (\d+), stored (\d+) \(acknowledged\), skipped (\d+), dropped (\d+), no tf (\d+), scenes opened (\d+) "
    r"closed (\d+), server failures (\d+), masked (\d+) \(dynamic pixels (\d+)\), without mask (\d+), masks refused "
    r"(\d+), grid imported (yes|no)")
_COUNT_NAMES = ("offered", "stored", "skipped", "dropped", "no_tf", "opened", "closed", "failures", "masked",
                "dynamic_pixels", "without_mask", "masks_refused", "grid_imported")


def node_counts(output):
    """The counts line the node prints at exit."""
    m = _COUNTS.search(output)
    if not m:
        raise AssertionError("the node logged no counts at exit:\n" + output)
    return {k: (v == "yes" if k == "grid_imported" else int(v)) for k, v in zip(_COUNT_NAMES, m.groups())}


def wait_analysed(c, timeout=60):
    """Until the map's keyframe analyses are all done (the server runs them in the background)."""
    deadline = time.monotonic() + timeout
    while True:
        queue = c.request("GET", "/v1/maps/home/analysis")
        if queue["depth"] == 0 and queue["running"] == 0:
            if queue["failed"]:
                raise AssertionError("keyframe analyses failed: %s" % queue)
            return
        if time.monotonic() > deadline:
            raise AssertionError("keyframe analyses still queued after %d s: %s" % (timeout, queue))
        time.sleep(0.1)


def memory_of(c):
    """What a map holds that import and bridge must agree on: scene models in id order, change events ('labelled'
    left out: the test labels the key itself), object instances, the occupancy layer."""
    scenes = []
    for s in sorted(c.request("GET", "/v1/maps/home/scenes")["scenes"], key=lambda s: s["id"]):
        w = c.request("GET", "/v1/maps/home/scenes/%d" % s["id"])
        scenes.append({"id": w["id"], "status": w["status"], "superseded_by": w["superseded_by"],
                       "frames": w["frames"], "persisted_frames": w["persisted_frames"], "started_ns": w["started_ns"],
                       "merged": [m["scene"] for m in (w["merge"] or {}).get("models_used", [])
                                  if m["premises"]["merged"]],
                       "position": w["pose"]["position"], "orientation": w["pose"]["orientation"]})
    events = []
    for e in c.request("GET", "/v1/maps/home/events?limit=1000")["events"]:
        if e["type"] == "labelled":
            continue
        segment = e["details"].get("segment") or {}
        events.append({"id": e["id"], "type": e["type"], "detection": e["detection"], "scene": e["scene"],
                       "instance": e["instance"], "label": e["label"], "points": segment.get("points"),
                       "centroid": segment.get("centroid_m"), "stamp_ns": e["stamp_ns"],
                       "evidence": [(k["keyframe"], k["role"]) for k in e["evidence"]]})
    instances = {i["id"]: i["position_m"] for i in c.request("GET", "/v1/maps/home/instances?limit=1000")["instances"]}
    try:
        occupancy = c.request("GET", "/v1/maps/home/layers/occupancy?format=pgm")
    except anchordb_client.ApiError as e:
        if e.status != 404:
            raise
        occupancy = None
    return {"scenes": scenes, "events": events, "instances": instances, "occupancy": occupancy}


def angle_between(q, p):
    return 2 * math.acos(min(1.0, abs(sum(a * b for a, b in zip(q, p)))))


class Inbox:
    """Messages of one topic, collected by a rospy subscriber."""

    def __init__(self, rospy, topic, cls):
        self.messages, self.lock = [], threading.Lock()
        self.sub = rospy.Subscriber(topic, cls, self._add, queue_size=100)

    def _add(self, m):
        with self.lock:
            self.messages.append(m)

    def wait_for(self, predicate, timeout=20):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            with self.lock:
                found = [m for m in self.messages if predicate(m)]
            if found:
                return found[-1]
            time.sleep(0.1)
        raise AssertionError("no matching message on %s within %d s" % (self.sub.name, timeout))

    def close(self):
        self.sub.unregister()


class RosBridgeTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.bin = os.environ.get("ANCHORDB_ROS_BIN")
        if not cls.bin or not os.access(cls.bin, os.X_OK):
            raise RuntimeError("ANCHORDB_ROS_BIN must name the anchordb_ros binary")
        cls.dir = tempfile.mkdtemp(prefix="anchordb-bridge-")
        cls.bag = os.path.join(cls.dir, "robot.bag")
        ros_bags.write_bag(cls.bag, ros_bags.ROBOT, SEED, with_mask=True, with_grid=True)
        cls.master = ros_graph.Master()
        os.environ.update({k: cls.master.env[k] for k in ("ROS_MASTER_URI", "ROS_HOSTNAME", "ROS_LOG_DIR")})
        import rospy  # after ROS_MASTER_URI is set
        cls.rospy = rospy
        rospy.init_node("anchordb_bridge_test", anonymous=True, disable_signals=True)

    @classmethod
    def tearDownClass(cls):
        cls.rospy.signal_shutdown("test done")
        cls.master.stop()
        shutil.rmtree(cls.dir, ignore_errors=True)

    def start_server(self):
        """An anchordb server on a fixed free port (it can be restarted on the same one)."""
        port = ros_graph.free_port()
        return harness.Server(self, extra_args=["--port", str(port)] + ros_bags.SERVER_SETTINGS)

    def start_node(self, server, **params):
        params.update({"server_port": server.port, "map": "home", "poll_period_s": 0.5})
        self.master.clear_params(NODE)  # an earlier node's private parameters
        node = ros_graph.Node(self.bin, self.master.env, params, {"depth/image": DEPTH, "depth/camera_info": INFO})
        self.addCleanup(node.remove_log)
        self.addCleanup(node.stop)
        topics = [DEPTH, INFO, "/tf", "/tf_static"] + [params[k] for k in ("mask_topic", "grid_topic") if k in params]
        self.master.wait_subscribed(NODE, topics)
        return node

    def inbox(self, topic, type_name):
        box = Inbox(self.rospy, topic, ros_graph.message_class(type_name))
        self.addCleanup(box.close)
        return box

    @staticmethod
    def scenes(c):
        """The map's scene models; none while the node has not created the map yet."""
        try:
            return c.request("GET", "/v1/maps/home/scenes")["scenes"]
        except anchordb_client.ApiError as e:
            if e.status != 404:
                raise
            return []

    def play(self):
        return subprocess.Popen(["rosbag", "play", "-q", "-d", "1", self.bag], env=self.master.env,
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)

    def imported(self):
        """`anchordb import rosbag` of the same bag with the same optional topics into a fresh database: its summary
        and its memory."""
        server = harness.Server(self, extra_args=ros_bags.SERVER_SETTINGS)
        server.client.create_map("home")
        server.stop()
        run = harness.run_cli(["import", "rosbag", "--db", server.db_path, "--map", "home", "--bag", self.bag,
                               "--mask-topic", ros_bags.MASK_TOPIC, "--grid-topic", ros_bags.GRID_TOPIC] +
                              ros_bags.SERVER_SETTINGS, timeout=300)
        self.assertEqual(run.returncode, 0, run.stdout + run.stderr)
        summary = json.loads(run.stdout.strip().splitlines()[-1])
        c = server.start()
        wait_analysed(c)
        return summary, memory_of(c)

    def compare(self, bridged, imported):
        """Asserts that the two memories agree; returns the largest differences found."""
        worst = {"position_m": 0.0, "angle_rad": 0.0, "centroid_m": 0.0, "instance_m": 0.0}
        self.assertEqual(len(bridged["scenes"]), len(imported["scenes"]))
        for b, i in zip(bridged["scenes"], imported["scenes"]):
            for key in ("id", "status", "superseded_by", "frames", "persisted_frames", "started_ns", "merged"):
                self.assertEqual(b[key], i[key], "scene %d: %s" % (i["id"], key))
            worst["position_m"] = max(worst["position_m"], math.dist(b["position"], i["position"]))
            worst["angle_rad"] = max(worst["angle_rad"], angle_between(b["orientation"], i["orientation"]))
        self.assertEqual(len(bridged["events"]), len(imported["events"]), (bridged["events"], imported["events"]))
        for b, i in zip(bridged["events"], imported["events"]):
            for key in ("type", "detection", "scene", "instance", "label", "points", "stamp_ns", "evidence"):
                self.assertEqual(b[key], i[key], "event %d: %s" % (i["id"], key))
            worst["centroid_m"] = max(worst["centroid_m"], math.dist(b["centroid"], i["centroid"]))
        self.assertEqual(sorted(bridged["instances"]), sorted(imported["instances"]))
        for k in imported["instances"]:
            worst["instance_m"] = max(worst["instance_m"], math.dist(bridged["instances"][k], imported["instances"][k]))
        self.assertIsNotNone(imported["occupancy"])
        self.assertEqual(bridged["occupancy"], imported["occupancy"])
        for key in ("position_m", "centroid_m", "instance_m"):
            self.assertLessEqual(worst[key], POSITION_TOLERANCE_M, worst)
        self.assertLessEqual(worst["angle_rad"], ANGLE_TOLERANCE_RAD, worst)
        return worst

    def test_same_memory_as_the_import_then_events_services_markers(self):
        server = self.start_server()
        c = server.client
        node = self.start_node(server, mask_topic=ros_bags.MASK_TOPIC, grid_topic=ros_bags.GRID_TOPIC)
        events = self.inbox(NODE + "/events", "anchordb_ros/ChangeEvent")
        play = self.play()
        self.assertEqual(play.wait(timeout=120), 0)
        added = events.wait_for(lambda m: m.type == "added", timeout=30)  # the second visit's begin keyframe
        time.sleep(1.0)  # the last images through tf and the server
        self.assertEqual(node.stop(), 0, node.output())
        counts = node_counts(node.output())
        self.assertEqual(counts["offered"], ros_bags.FRAMES_WITH_POSE, node.output())
        self.assertEqual((counts["stored"], counts["dropped"], counts["failures"]), (sum(MODEL_FRAMES), 0, 0))
        self.assertEqual((counts["opened"], counts["closed"]), (3, 3))
        self.assertEqual((counts["without_mask"], counts["masks_refused"], counts["grid_imported"]), (0, 0, True))
        wait_analysed(c)
        bridged = memory_of(c)
        summary, imported = self.imported()
        self.assertEqual((counts["masked"], counts["dynamic_pixels"]), (summary["frames_masked"], summary["dynamic_pixels"]))
        self.assertGreater(counts["dynamic_pixels"], 0)
        worst = self.compare(bridged, imported)
        self.assertEqual([s["persisted_frames"] for s in bridged["scenes"]], MODEL_FRAMES)
        self.assertEqual([(e["type"], e["detection"]) for e in bridged["events"]], [("added", "meanwhile")])
        lines = ["import vs bridge, same bag: %d scene models, %d change events, %d instances; node %s" % (
            len(imported["scenes"]), len(imported["events"]), len(imported["instances"]), counts)]
        for b, i in zip(bridged["scenes"], imported["scenes"]):
            lines.append("  scene %d %-10s frames %2d  import (%.4f, %.4f, %.4f)  bridge (%.4f, %.4f, %.4f)" % (
                i["id"], i["status"], i["frames"], *i["position"], *b["position"]))
        for b, i in zip(bridged["events"], imported["events"]):
            lines.append("  event %d %s %s instance %d, %d points, centroid import (%.4f, %.4f, %.4f) bridge "
                         "(%.4f, %.4f, %.4f)" % (i["id"], i["type"], i["detection"], i["instance"], i["points"],
                                                  *i["centroid"], *b["centroid"]))
        lines.append("  dynamic input: %d frames with a mask, %d dynamic pixels (both); occupancy layer %d bytes (both)"
                     % (counts["masked"], counts["dynamic_pixels"], len(imported["occupancy"])))
        lines.append("  largest differences: %s" % ", ".join("%s %.2g" % kv for kv in worst.items()))
        print("\n" + "\n".join(lines))

        # The event came on ~events as over HTTP, with the instance's position and its evidence keyframes.
        (http,) = bridged["events"]
        self.assertEqual((added.id, added.type, added.detection, added.instance), (http["id"], "added", "meanwhile",
                                                                                    http["instance"]))
        key = c.request("GET", "/v1/maps/home/instances/%d" % http["instance"])
        self.assertLess(math.dist((added.position.x, added.position.y, added.position.z), key["position_m"]), 1e-6)
        self.assertEqual(list(added.evidence_keyframes), [k for k, _ in http["evidence"]])
        self.assertEqual(added.stamp.to_nsec(), http["stamp_ns"])
        self.check_services_events_markers(server, key)

    def check_services_events_markers(self, server, key):
        """A node on the server that holds the detected key: ~label names it, the label's event comes on ~events,
        the markers show it, ~where_is answers for it."""
        node = self.start_node(server)
        events = self.inbox(NODE + "/events", "anchordb_ros/ChangeEvent")
        markers = self.inbox(NODE + "/instances", "visualization_msgs/MarkerArray")
        where_is = self.rospy.ServiceProxy(NODE + "/where_is", ros_graph.service_class("anchordb_ros/WhereIs"))
        label = self.rospy.ServiceProxy(NODE + "/label", ros_graph.service_class("anchordb_ros/Label"))
        self.rospy.wait_for_service(NODE + "/label", timeout=20)
        self.assertFalse(where_is(label="keys").found)  # nobody said what it is yet
        labelled = label(instance=key["id"], label="keys", from_operator=True)
        self.assertTrue(labelled.ok, labelled.message)
        refused = label(instance=key["id"], label="wallet", from_operator=False)  # an operator made it "keys"
        self.assertFalse(refused.ok)
        self.assertIn("operator", refused.message)
        self.assertFalse(label(instance=999999, label="wallet", from_operator=True).ok)
        event = events.wait_for(lambda m: m.type == "labelled" and m.instance == key["id"])
        self.assertEqual(event.label, "keys")
        self.assertLess(math.dist((event.position.x, event.position.y, event.position.z), key["position_m"]), 1e-6)
        markers.wait_for(lambda a: any(m.text == "keys" and m.id == key["id"] for m in a.markers))
        answer = where_is(label="keys")
        self.assertTrue(answer.found, answer)
        self.assertEqual(answer.pose.header.frame_id, "map")
        p = answer.pose.pose.position
        self.assertLess(math.dist((p.x, p.y, p.z), key["position_m"]), 1e-6)
        self.assertEqual(answer.last_seen.to_nsec(), key["last_seen_ns"])
        self.assertTrue(answer.sentence)
        self.assertFalse(where_is(label="umbrella").found)
        self.assertEqual(node.stop(), 0, node.output())

    def test_probability_layer_as_occupancy_grid(self):
        server = self.start_server()
        self.start_node(server, layers="people")
        c = server.client
        room = harness.SyntheticMap(40, 30, 0.1, origin=(-1.0, -2.0, 0.0))
        try:
            c.create_map("home")
        except anchordb_client.ApiError as e:  # the node created it first
            self.assertEqual(e.status, 409)
        c.import_occupancy("home", "occ", room.yaml(), room.pgm())
        c.create_layer("home", "people", {"kind": "probability", "base": "occ"})
        grids = self.inbox(NODE + "/layers/people", "nav_msgs/OccupancyGrid")
        first = grids.wait_for(lambda g: len(g.data) > 0)
        self.assertEqual((first.info.width, first.info.height), (40, 30))
        self.assertAlmostEqual(first.info.resolution, 0.1, places=6)
        self.assertEqual((first.info.origin.position.x, first.info.origin.position.y), (-1.0, -2.0))
        self.assertEqual(first.header.frame_id, "map")
        self.assertEqual(set(first.data), {50})  # nothing observed: log-odds 0
        # A person seen in front of a sensor at (0, -0.5) looking along +x: raised cells, a lowered free cone.
        pose = {"position": [0.0, -0.5, 0.0], "orientation": [0.0, 0.0, 0.0, 1.0]}
        c.observe("home", "people", pose, 1.0, 2.5, [[[1.0, -0.7], [1.4, -0.7], [1.4, -0.3], [1.0, -0.3]]])
        second = grids.wait_for(lambda g: any(v > 50 for v in g.data))
        raw = c.request("GET", "/v1/maps/home/layers/people?format=raw")
        log_odds = struct.unpack("<%df" % (40 * 30), raw)
        expected = [round(100 / (1 + math.exp(-l))) for l in log_odds]
        self.assertEqual(list(second.data), expected)  # same cells in the same order
        self.assertGreater(sum(1 for v in expected if v > 50), 10)
        self.assertGreater(sum(1 for v in expected if v < 50), 10)

    def test_server_going_away_loses_no_acknowledged_frame(self):
        Log = ros_graph.message_class("rosgraph_msgs/Log")
        rosout = self.inbox("/rosout", "rosgraph_msgs/Log")
        server = self.start_server()
        node = self.start_node(server, max_backoff_s=0.5)  # retried every 0.5 s: back well before the model at B opens
        play = self.play()
        deadline = time.monotonic() + 30
        while not self.scenes(server.client):  # the model at A has opened
            self.assertLess(time.monotonic(), deadline, "no scene model opened:\n" + node.output())
            time.sleep(0.05)
        server.stop()
        time.sleep(1.0)  # frames of A arrive while the server is away (A lasts 2 s)
        server.start()
        self.assertEqual(play.wait(timeout=120), 0)
        time.sleep(1.0)
        self.assertIsNone(node.proc.poll(), "the node died:\n" + node.output())
        self.assertEqual(node.stop(), 0, node.output())
        counts = node_counts(node.output())
        self.assertGreater(counts["dropped"], 0, node.output())
        rosout.wait_for(lambda m: m.name == NODE and m.level == Log.WARN and "not stored" in m.msg)
        scenes = self.scenes(server.client)
        held = sum(s["persisted_frames"] for s in scenes)
        print("\nserver away: node %s; server holds %d frames in %d scene models" % (counts, held, len(scenes)))
        # Every acknowledged frame is held; a frame the server stored while going down may have lost its answer
        # (not acknowledged, so not counted), at most one per failed request.
        message = "server holds %d frames, the node acknowledged %d\n%s" % (held, counts["stored"], node.output())
        self.assertGreaterEqual(held, counts["stored"], message)
        self.assertLessEqual(held, counts["stored"] + counts["failures"], message)
        # The models at B and at A again opened after the server came back, with all their frames.
        by_id = sorted(scenes, key=lambda s: s["id"])
        self.assertEqual([s["persisted_frames"] for s in by_id[-2:]], MODEL_FRAMES[1:], "%s\n%s" % (by_id, node.output()))


if __name__ == "__main__":
    unittest.main()
