"""Killing one of two anchordb servers on one PostgreSQL database (issue 31, acceptance 2): a robot streams depth
frames into an observing scene model through server A; A gets kill -9 half-way; the robot goes on through server B.
B serves the model from the database (its last checkpoint and the frame journal, where every acknowledged frame was
committed before its answer): it holds every frame A acknowledged, it stays observing, it takes the rest, and its
layers are byte for byte those of the same frames streamed through one server without interruption (a second map of
the same database, fed through B alone)."""

import struct
import unittest

import harness

W, H = 64, 48
CAMERA = {"width": W, "height": H, "fx": 52.5, "fy": 52.5, "cx": 31.5, "cy": 23.5}
POSE = {"position": [0.0, 0.0, 1.0], "orientation": [0.0, 0.0, 0.0, 1.0]}
FRAMES = 60
KILLED_AFTER = 37  # frames acknowledged by A before its kill (not at a checkpoint: every 30 frames by default)
T0_NS = 1_780_000_000_000_000_000
LAYERS = ("static", "movable", "dynamic", "reliability")


def frame(index):
    """A wall at 2 m with a box at 1.2 m that moves 10 px to the right every 15 frames: movable evidence, keyframes
    when it settles."""
    depth = [2000] * (W * H)
    x0 = 8 + 10 * (index // 15)
    for y in range(16, 32):
        for x in range(x0, x0 + 12):
            depth[y * W + x] = 1200
    return struct.pack("<%dH" % (W * H), *depth)


class ServerKillTest(unittest.TestCase):
    def setUp(self):
        _, self.uri, _ = harness.pg_scratch(self)

    def send(self, client, map_id, scene, index):
        path = "/v1/maps/%s/scenes/%d/frames?stamp=%d" % (map_id, scene, T0_NS + index * 100_000_000)
        r = client.request("POST", path, frame(index), headers={"Content-Type": "application/octet-stream"}, raw=True)
        self.assertEqual(r.status, 200, r.body)

    def scene(self, client, map_id, scene):
        return client.request("GET", "/v1/maps/%s/scenes/%d" % (map_id, scene))

    def layers(self, client, map_id, scene):
        out = {}
        for layer in LAYERS:
            r = client.request("GET", "/v1/maps/%s/scenes/%d/layers/%s?format=raw" % (map_id, scene, layer), raw=True)
            self.assertEqual(r.status, 200, r.body)
            out[layer] = r.body
        return out

    def open_scene(self, client, map_id):
        client.request("POST", "/v1/maps", {"id": map_id})
        return client.request("POST", "/v1/maps/%s/scenes" % map_id, {"camera": CAMERA, "pose": POSE})["id"]

    def test_the_killed_servers_observing_model_continues_on_the_other_without_a_lost_frame(self):
        a = harness.Server(self, db_path=self.uri)
        b = harness.Server(self, db_path=self.uri)
        ca, cb = a.client, b.client

        scene = self.open_scene(ca, "home")
        for i in range(KILLED_AFTER):
            self.send(ca, "home", scene, i)
        a.kill()

        seen = self.scene(cb, "home", scene)  # B has never served this model: from the database
        self.assertEqual(seen["status"], "observing")
        self.assertEqual(seen["frames"], KILLED_AFTER, "frames acknowledged by the killed server")
        for i in range(KILLED_AFTER, FRAMES):
            self.send(cb, "home", scene, i)
        continued = self.scene(cb, "home", scene)
        self.assertEqual(continued["frames"], FRAMES)
        self.assertEqual(continued["status"], "observing")

        reference = self.open_scene(cb, "reference")
        for i in range(FRAMES):
            self.send(cb, "reference", reference, i)
        expected = self.layers(cb, "reference", reference)
        got = self.layers(cb, "home", scene)
        self.assertTrue(any(expected["movable"]), "the reference run saw no movable evidence")
        for layer in LAYERS:
            self.assertEqual(len(got[layer]), len(expected[layer]), layer)
            differing = sum(1 for x, y in zip(got[layer], expected[layer]) if x != y)
            self.assertEqual(differing, 0, "%s layer: %d of %d bytes differ from the uninterrupted run" % (
                layer, differing, len(expected[layer])))
        kinds = [k["kind"] for k in continued["keyframes"]]
        self.assertEqual(kinds, [k["kind"] for k in self.scene(cb, "reference", reference)["keyframes"]])


if __name__ == "__main__":
    unittest.main()
