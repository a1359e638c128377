"""The anchordb_ros bridge node against a real rosmaster (free loopback port), a real anchordb server and `rosbag
play` of the bag of test_ros_rosbag_import.py (ros_bags.py).

Checks that the node makes the same scene models as `anchordb import rosbag` of the same bag (places, frames), that
its where_is and label services answer from the server, that the label's change event arrives on ~events with the
instance's position and the instance on ~instances as markers, and that an anchordb server stopped in the middle of
the bag and started again crashes nothing, is reported on /rosout, and loses no acknowledged frame (the frames the
server holds are the frames the node counted as stored).

Needs Debian's ROS 1 (rosmaster, rosbag, rospy, genpy, genmsg) and the anchordb_ros binary ($ANCHORDB_ROS_BIN):
registered by ctest only when both were built (label `ros`).
"""

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


def stored_count(output):
    m = re.search(r"offered (\d+), stored (\d+) \(acknowledged\), skipped (\d+), dropped (\d+), no tf (\d+), "
                  r"scenes opened (\d+) closed (\d+), server failures (\d+)", output)
    if not m:
        raise AssertionError("the node logged no counts at exit:\n" + output)
    names = ("offered", "stored", "skipped", "dropped", "no_tf", "opened", "closed", "failures")
    return {k: int(v) for k, v in zip(names, m.groups())}


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


class RosBridgeTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.bin = os.environ.get("ANCHORDB_ROS_BIN")
        if not cls.bin or not os.access(cls.bin, os.X_OK):
            raise RuntimeError("ANCHORDB_ROS_BIN must name the anchordb_ros binary")
        cls.dir = tempfile.mkdtemp(prefix="anchordb-bridge-")
        cls.bag = os.path.join(cls.dir, "robot.bag")
        ros_bags.write_bag(cls.bag, ros_bags.ROBOT, SEED)
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

    def start(self, **params):
        """An anchordb server on a fixed free port (it is restarted on the same one) and the node."""
        port = ros_graph.free_port()
        server = harness.Server(self, extra_args=["--port", str(port)])
        params.update({"server_port": port, "map": "home", "poll_period_s": 0.5})
        node = ros_graph.Node(self.bin, self.master.env, params, {"depth/image": DEPTH, "depth/camera_info": INFO})
        self.addCleanup(node.remove_log)
        self.addCleanup(node.stop)
        self.master.wait_subscribed(NODE, [DEPTH, INFO, "/tf", "/tf_static"])
        return server, node

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

    def places(self, c):
        """[(scene id, frames)] of the scene models near place A and place B."""
        out = []
        for place in (ros_bags.PLACE_A, ros_bags.PLACE_B):
            _, centre = ros_bags.optical_in_map(place)
            near = c.request("GET", "/v1/maps/home/scenes?near=%.4f,%.4f,%.4f&radius=0.05" % tuple(centre))["scenes"]
            out.append([c.request("GET", "/v1/maps/home/scenes/%d" % s["id"])["persisted_frames"] for s in near])
        return out

    def imported_places(self):
        server = harness.Server(self)
        server.client.create_map("home")
        server.stop()
        run = harness.run_cli(["import", "rosbag", "--db", server.db_path, "--map", "home", "--bag", self.bag])
        self.assertEqual(run.returncode, 0, run.stderr)
        return self.places(server.start())

    def check_services_events_markers(self, c):
        ChangeEvent = ros_graph.message_class("anchordb_ros/ChangeEvent")
        MarkerArray = ros_graph.message_class("visualization_msgs/MarkerArray")
        events = Inbox(self.rospy, NODE + "/events", ChangeEvent)
        markers = Inbox(self.rospy, NODE + "/instances", MarkerArray)
        keys = c.create_instance("home", "keys", [0.1, 1.2, 0.75], kind="object")
        where_is = self.rospy.ServiceProxy(NODE + "/where_is", ros_graph.service_class("anchordb_ros/WhereIs"))
        answer = where_is(label="keys")
        self.assertTrue(answer.found, answer)
        p = answer.pose.pose.position
        self.assertEqual(answer.pose.header.frame_id, "map")
        self.assertLess(math.dist((p.x, p.y, p.z), (0.1, 1.2, 0.75)), 1e-6)
        self.assertTrue(answer.sentence)
        self.assertFalse(where_is(label="umbrella").found)
        label = self.rospy.ServiceProxy(NODE + "/label", ros_graph.service_class("anchordb_ros/Label"))
        refused = label(instance=keys["id"], label="wallet", from_operator=False)  # an operator made it "keys"
        self.assertFalse(refused.ok)
        self.assertIn("operator", refused.message)
        labelled = label(instance=keys["id"], label="wallet", from_operator=True)
        self.assertTrue(labelled.ok, labelled.message)
        self.assertFalse(label(instance=999999, label="wallet", from_operator=True).ok)
        event = events.wait_for(lambda m: m.type == "labelled" and m.instance == keys["id"])
        self.assertEqual(event.label, "wallet")
        self.assertLess(math.dist((event.position.x, event.position.y, event.position.z), (0.1, 1.2, 0.75)), 1e-6)
        markers.wait_for(lambda a: any(m.text == "wallet" and m.id == keys["id"] for m in a.markers))

    def test_same_models_as_the_import_services_events_markers(self):
        server, node = self.start()
        play = self.play()
        self.assertEqual(play.wait(timeout=120), 0)
        self.check_services_events_markers(server.client)
        time.sleep(1.0)  # the last images through tf and the server
        self.assertEqual(node.stop(), 0, node.output())
        counts = stored_count(node.output())
        self.assertEqual(counts["offered"], ros_bags.HOLD_A + ros_bags.DRIVE - 1 + ros_bags.HOLD_B, node.output())
        self.assertEqual(counts["dropped"], 0, node.output())
        bridged = self.places(server.client)
        print("\nbridge: node %s; frames of the models at A and B %s" % (counts, bridged))
        self.assertEqual(bridged, [[16], [12]])
        self.assertEqual(bridged, self.imported_places())

    def test_probability_layer_as_occupancy_grid(self):
        server, node = self.start(layers="people")
        c = server.client
        room = harness.SyntheticMap(40, 30, 0.1, origin=(-1.0, -2.0, 0.0))
        try:
            c.create_map("home")
        except anchordb_client.ApiError as e:  # the node created it first
            self.assertEqual(e.status, 409)
        c.import_occupancy("home", "occ", room.yaml(), room.pgm())
        c.create_layer("home", "people", {"kind": "probability", "base": "occ"})
        OccupancyGrid = ros_graph.message_class("nav_msgs/OccupancyGrid")
        grids = Inbox(self.rospy, NODE + "/layers/people", OccupancyGrid)
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
        rosout = Inbox(self.rospy, "/rosout", Log)
        server, node = self.start(max_backoff_s=0.5)  # retried every 0.5 s: back well before the model at B opens
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
        counts = stored_count(node.output())
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
        self.assertEqual(self.places(server.client)[1], [12])  # the model at B, opened after the server came back


if __name__ == "__main__":
    unittest.main()
