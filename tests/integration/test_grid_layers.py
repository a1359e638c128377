"""Grid layers over HTTP (thesis 3.3.1, 3.4.2): map_server import/export round trips of generated maps, the
observation update of a probability layer (raised in the stimulus, lowered in view, unchanged behind a wall and
outside the field of view or range), fused layers against a Python computation, label layers, regions, and the
dependency rule for deleting layers."""

import math
import struct
import unittest

import harness
from anchordb_client import ApiError

HIT = math.log(0.7 / 0.3)
MISS = math.log(0.4 / 0.6)
CLAMP_MAX = math.log(0.97 / 0.03)
CLAMP_MIN = math.log(0.12 / 0.88)


def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


def probability(log_odds):
    """The server's probability of a stored float32 log-odds value, rounded to float32 as it stores it."""
    return f32(1.0 - 1.0 / (1.0 + math.exp(log_odds)))


def point_in_polygon(x, y, polygon):
    inside = False
    for k in range(len(polygon)):
        (ax, ay), (bx, by) = polygon[k], polygon[(k + 1) % len(polygon)]
        if (ay <= y) != (by <= y) and x < ax + (y - ay) * (bx - ax) / (by - ay):
            inside = not inside
    return inside


def rect(x0, y0, x1, y1):
    return [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]


def yaw_pose(x, y, yaw):
    return harness.identity_pose(x, y, yaw)


class RoundTripTest(unittest.TestCase):
    """map_server import -> export gives the same YAML values and the same pixels."""

    @classmethod
    def setUpClass(cls):
        cls.server = harness.Server(None)
        cls.c = cls.server.client
        cls.c.create_map("rt")

    @classmethod
    def tearDownClass(cls):
        cls.server.close()

    def round_trip(self, name, m, image_bytes, yaml_bytes=None):
        c = self.c
        yaml_in = yaml_bytes or m.yaml()
        info = c.import_occupancy("rt", name, yaml_in, image_bytes)
        self.assertEqual(info["kind"], "occupancy")
        self.assertEqual(info["geometry"]["width_cells"], m.width)
        self.assertEqual(info["geometry"]["height_cells"], m.height)
        yaml_out = c.get_layer("rt", name, "yaml")
        values_in, values_out = harness.parse_map_yaml(yaml_in), harness.parse_map_yaml(yaml_out)
        self.assertEqual(values_out.pop("image"), name + ".pgm")
        values_in.pop("image")
        self.assertEqual(set(values_out), set(values_in), yaml_out)
        for key, value in values_in.items():
            if isinstance(value, list):
                self.assertEqual([float(v) for v in values_out[key]], [float(v) for v in value], key)
            elif isinstance(value, float):
                self.assertEqual(float(values_out[key]), value, key)
            else:
                self.assertEqual(values_out[key], value, key)
        w, h, maxval, pixels = harness.parse_pgm(c.get_layer("rt", name, "pgm"))
        self.assertEqual((w, h, maxval), (m.width, m.height, 255))
        self.assertEqual(pixels, m.image_pixels)
        pw, ph, png_pixels = harness.decode_png_grey(c.get_layer("rt", name, "png"))
        self.assertEqual((pw, ph), (m.width, m.height))
        self.assertEqual(png_pixels, m.image_pixels)
        raw = c.get_layer("rt", name, "raw")
        self.assertEqual(c.last_headers["x-grid-width"], str(m.width))
        self.assertEqual(c.last_headers["x-grid-height"], str(m.height))
        self.assertEqual(raw, m.image_pixels)
        return values_out

    def test_pgm_round_trip(self):
        m = harness.SyntheticMap(57, 43, 0.05, origin=(-1.25, -0.75, 0.0), walls=[(20, 0, 21, 30), (5, 25, 40, 26)],
                                 unknown=[(45, 30, 56, 42), (0, 0, 3, 3)])
        m.fill(30, 5, 35, 10, 128)  # a grey (uncertain) patch
        self.round_trip("pgm", m, m.pgm())

    def test_png_import_gives_the_same_export(self):
        m = harness.SyntheticMap(57, 43, 0.05, origin=(-1.25, -0.75, 0.0), walls=[(20, 0, 21, 30)],
                                 unknown=[(45, 30, 56, 42)])
        self.round_trip("png", m, m.png())
        # The PGM and the PNG of the same pixels give identical exports.
        self.c.import_occupancy("rt", "png-as-pgm", m.yaml(), m.pgm())
        for fmt in ("pgm", "yaml", "raw", "png"):
            self.assertEqual(self.c.get_layer("rt", "png", fmt).replace(b"png.pgm", b"X"),
                             self.c.get_layer("rt", "png-as-pgm", fmt).replace(b"png-as-pgm.pgm", b"X"), fmt)

    def test_awkward_yaml_values_survive(self):
        m = harness.SyntheticMap(31, 17, 0.025, origin=(-12.345678901234567, 3.3000000000000003, 0.1),
                                 negate=1, occupied_thresh=0.7001, free_thresh=0.1999, mode="scale")
        self.round_trip("awkward", m, m.pgm())

    def test_ascii_pgm_imports(self):
        m = harness.SyntheticMap(12, 9, 0.1, walls=[(5, 0, 5, 8)], unknown=[(8, 5, 11, 8)])
        ascii_pgm = b"P2\n# ascii\n12 9\n255\n" + b"\n".join(
            b" ".join(b"%d" % p for p in m.image_pixels[r * 12:(r + 1) * 12]) for r in range(9)) + b"\n"
        self.round_trip("ascii", m, ascii_pgm)

    def test_occupancy_statistics_follow_map_server_thresholds(self):
        m = harness.SyntheticMap(20, 10, 0.1, walls=[(10, 0, 10, 9)], unknown=[(15, 5, 18, 8)])
        self.c.import_occupancy("rt", "stats", m.yaml(), m.pgm())
        stats = self.c.get_layer("rt", "stats", statistics=True)["statistics"]
        self.assertEqual(stats, {"occupied_cells": sum(1 for v in m.cells if v == harness.OCCUPIED),
                                 "free_cells": sum(1 for v in m.cells if v == harness.FREE),
                                 "unknown_cells": sum(1 for v in m.cells if v == harness.UNKNOWN)})


class ProbabilityLayerTest(unittest.TestCase):
    """An 8 m x 6 m room, 0.1 m cells, a wall at x = 3.0..3.1 m, y = 1.5..3.6 m; the sensor at (1, 2.5)."""

    MAP = harness.SyntheticMap(80, 60, 0.1, walls=[(30, 15, 30, 35)])
    SENSOR = (1.0, 2.5)
    FOV = math.pi / 2
    RANGE = 4.0
    IN_VIEW = rect(2.0, 2.6, 2.5, 3.0)        # in front of the wall, above the heading: raised
    BEHIND_WALL = rect(3.5, 2.0, 4.0, 3.0)    # in the wall's shadow: unchanged
    OUT_OF_RANGE = rect(4.5, 4.9, 4.9, 5.2)   # within the fov, > 4 m away: unchanged

    @classmethod
    def setUpClass(cls):
        cls.server = harness.Server(None)
        c = cls.c = cls.server.client
        c.create_map("g")
        c.import_occupancy("g", "occ", cls.MAP.yaml(), cls.MAP.pgm())

    @classmethod
    def tearDownClass(cls):
        cls.server.close()

    def tearDown(self):
        self.server.check_alive()

    def raw(self, layer, fmt="f"):
        data = self.c.get_layer("g", layer, "raw")
        w, h = int(self.c.last_headers["x-grid-width"]), int(self.c.last_headers["x-grid-height"])
        self.assertEqual((w, h), (self.MAP.width, self.MAP.height))
        size = struct.calcsize("<" + fmt)
        self.assertEqual(len(data), w * h * size)
        return list(struct.unpack("<%d%s" % (w * h, fmt), data))

    def observe(self, layer, stimulus, sensor=None, yaw=0.0, fov=None, rng=None):
        sensor = sensor or self.SENSOR
        return self.c.observe("g", layer, yaw_pose(sensor[0], sensor[1], yaw), fov or self.FOV, rng or self.RANGE,
                              stimulus)

    def value_at(self, values, x, y):
        ix, iy = self.MAP.cell_of(x, y)
        return values[iy * self.MAP.width + ix]

    def test_observation_raises_lowers_and_respects_walls_fov_and_range(self):
        c = self.c
        c.create_layer("g", "obs", {"kind": "probability", "base": "occ"})
        self.assertEqual(self.raw("obs"), [0.0] * (80 * 60))
        stimulus = [self.IN_VIEW, self.BEHIND_WALL, self.OUT_OF_RANGE]
        r = self.observe("obs", stimulus)
        self.assertEqual(r["version"], 2)
        values = self.raw("obs")
        raised = [i for i, v in enumerate(values) if abs(v - HIT) < 1e-5]
        lowered = [i for i, v in enumerate(values) if abs(v - MISS) < 1e-5]
        self.assertEqual(len(raised) + len(lowered), sum(1 for v in values if v != 0.0), "values other than hit/miss")
        self.assertEqual(r["cells_raised"], len(raised))
        self.assertEqual(r["cells_lowered"], len(lowered))
        # IN_VIEW covers 5 x 4 cells, all visible.
        self.assertEqual(len(raised), 20)
        sx, sy = self.SENSOR
        for i in raised + lowered:
            ix, iy = i % 80, i // 80
            x, y = self.MAP.cell_center(ix, iy)
            dist = math.hypot(x - sx, y - sy)
            angle = abs(math.atan2(y - sy, x - sx))
            self.assertLessEqual(dist, self.RANGE + 1e-9, (ix, iy))
            self.assertLessEqual(angle, self.FOV / 2 + 1e-9, (ix, iy))
            self.assertNotEqual(self.MAP.at(ix, iy), harness.OCCUPIED, (ix, iy))
            in_stimulus = any(point_in_polygon(x, y, p) for p in stimulus)
            self.assertEqual(i in raised, in_stimulus, (ix, iy))
            if x > 3.1:  # beyond the wall: the line of sight must pass above or below it
                y_at_wall = sy + (y - sy) * (3.05 - sx) / (x - sx)
                self.assertFalse(1.55 <= y_at_wall <= 3.55, "cell (%d, %d) behind the wall changed" % (ix, iy))
        # Sample cells of each class, with row iy = 0 at the bottom.
        self.assertAlmostEqual(self.value_at(values, 2.25, 2.8), HIT, places=5)    # stimulus, visible
        self.assertAlmostEqual(self.value_at(values, 2.25, 2.2), MISS, places=5)   # visible, no stimulus
        self.assertAlmostEqual(self.value_at(values, 1.5, 2.5), MISS, places=5)
        self.assertEqual(self.value_at(values, 3.75, 2.5), 0.0)                    # stimulus behind the wall
        self.assertEqual(self.value_at(values, 3.05, 2.5), 0.0)                    # the wall itself
        self.assertEqual(self.value_at(values, 4.7, 5.05), 0.0)                    # stimulus beyond the range
        self.assertAlmostEqual(self.value_at(values, 3.87, 4.51), MISS, places=5)  # same ray, within range
        self.assertEqual(self.value_at(values, 1.05, 3.5), 0.0)                    # beside the sensor: outside fov
        self.assertEqual(self.value_at(values, 0.5, 2.5), 0.0)                     # behind the sensor
        self.assertEqual(self.value_at(values, 2.25, 5.5), 0.0)                    # outside the fov
        self.assertGreater(r["stimulus_cells_outside_view"], 0)
        self.assertGreater(r["cells_unchanged_blocked"], 0)
        info = c.get_layer("g", "obs")
        self.assertEqual((info["version"], info["observations"]), (2, 1))

    def test_heading_comes_from_the_orientation(self):
        # Looking along +y (yaw pi/2) from (1, 2.5): a stimulus above the sensor is raised, one ahead on +x is not.
        self.c.create_layer("g", "yaw", {"kind": "probability", "base": "occ"})
        self.observe("yaw", [rect(0.8, 3.5, 1.2, 3.9), rect(2.0, 2.3, 2.4, 2.7)], yaw=math.pi / 2, fov=1.0)
        values = self.raw("yaw")
        self.assertAlmostEqual(self.value_at(values, 1.0, 3.7), HIT, places=5)
        self.assertEqual(self.value_at(values, 2.2, 2.5), 0.0)

    def test_repeated_observations_clamp(self):
        self.c.create_layer("g", "clamp", {"kind": "probability", "base": "occ"})
        for k in range(6):
            r = self.observe("clamp", [self.IN_VIEW])
            self.assertEqual(r["version"], k + 2)
        values = self.raw("clamp")
        self.assertAlmostEqual(self.value_at(values, 2.25, 2.8), f32(CLAMP_MAX), places=5)
        self.assertAlmostEqual(self.value_at(values, 2.25, 2.2), f32(CLAMP_MIN), places=5)
        # Custom parameters are used and reported.
        params = {"hit": 0.9, "miss": 0.2, "clamp_min": 0.3, "clamp_max": 0.95}
        info = self.c.create_layer("g", "custom", {"kind": "probability", "base": "occ", "log_odds": params})
        self.assertEqual(info["log_odds"], params)
        self.observe("custom", [self.IN_VIEW])
        values = self.raw("custom")
        self.assertAlmostEqual(self.value_at(values, 2.25, 2.8), math.log(9.0), places=5)
        self.assertAlmostEqual(self.value_at(values, 2.25, 2.2), math.log(0.3 / 0.7), places=5)  # clamped at once

    def test_fused_layers_match_python(self):
        c = self.c
        c.create_layer("g", "fa", {"kind": "probability", "base": "occ"})
        c.create_layer("g", "fb", {"kind": "probability", "base": "occ"})
        c.create_layer("g", "fc", {"kind": "probability", "base": "occ"})
        self.observe("fa", [rect(1.5, 2.0, 2.5, 3.0)])
        self.observe("fa", [rect(1.5, 2.0, 2.0, 3.0)])
        self.observe("fb", [rect(2.0, 1.6, 2.8, 2.6)], sensor=(1.0, 1.8), yaw=0.3)
        self.observe("fc", [rect(1.8, 2.2, 2.2, 3.4)], sensor=(2.0, 4.5), yaw=-math.pi / 2, fov=2.0)
        la, lb, lc = self.raw("fa"), self.raw("fb"), self.raw("fc")
        ta, tb, tc = 0.6, 0.45, 0.55
        ma = [probability(v) >= ta for v in la]
        mb = [probability(v) >= tb for v in lb]
        mc = [probability(v) >= tc for v in lc]
        expected = {
            "and": [a and b for a, b in zip(ma, mb)],
            "or": [a or b for a, b in zip(ma, mb)],
            "and_not": [a and not b for a, b in zip(ma, mb)],
            "xor": [a != b for a, b in zip(ma, mb)],
        }
        for op, want in expected.items():
            with self.subTest(op=op):
                info = c.create_layer("g", "fused_" + op, {"kind": "fused", "op": op, "operands": [
                    {"layer": "fa", "threshold": ta}, {"layer": "fb", "threshold": tb}]})
                self.assertEqual(info["kind"], "fused")
                got = self.raw("fused_" + op, "B")
                self.assertEqual(c.last_headers.get("x-element"), "u8-mask-cell-order")
                self.assertEqual(got, [1 if v else 0 for v in want])
                self.assertGreater(sum(got), 0, "degenerate test: %s is empty" % op)
        # Three operands: xor is parity, and_not removes every later operand.
        three = [{"layer": "fa", "threshold": ta}, {"layer": "fb", "threshold": tb}, {"layer": "fc", "threshold": tc}]
        c.create_layer("g", "fused_xor3", {"kind": "fused", "op": "xor", "operands": three})
        c.create_layer("g", "fused_and_not3", {"kind": "fused", "op": "and_not", "operands": three})
        self.assertEqual(self.raw("fused_xor3", "B"), [(a + b + x) % 2 for a, b, x in zip(ma, mb, mc)])
        self.assertEqual(self.raw("fused_and_not3", "B"),
                         [1 if a and not b and not x else 0 for a, b, x in zip(ma, mb, mc)])
        # A fused layer follows its operands: a new observation changes it.
        before = self.raw("fused_or", "B")
        self.observe("fb", [rect(1.5, 3.2, 2.0, 3.6)], yaw=0.6)
        mb = [probability(v) >= tb for v in self.raw("fb")]
        after = self.raw("fused_or", "B")
        self.assertNotEqual(after, before)
        self.assertEqual(after, [1 if a or b else 0 for a, b in zip(ma, mb)])
        # Regions of a fused layer are the connected components of its mask.
        regions = c.regions("g", "fused_and", threshold=0.5)["regions"]
        self.assertEqual(sum(r["cells"] for r in regions), sum(self.raw("fused_and", "B")))

    def test_label_layer_painting(self):
        c = self.c
        info = c.create_layer("g", "rooms", {"kind": "label", "base": "occ", "labels": {"1": "kitchen"}})
        self.assertEqual(info["labels"], {"1": "kitchen"})
        r = c.paint_label("g", "rooms", "kitchen", [rect(1.0, 1.0, 2.0, 1.5)])
        self.assertEqual((r["label_id"], r["cells"]), (1, 50))
        r = c.paint_label("g", "rooms", "hall", [rect(1.5, 1.2, 2.5, 2.0), rect(6.0, 4.0, 6.3, 4.3)])
        self.assertEqual(r["label_id"], 2)
        self.assertEqual(r["cells"], 10 * 8 + 9)
        labels = self.raw("rooms", "H")
        self.assertEqual(c.last_headers.get("x-element"), "u16-label-cell-order")
        expected = [0] * (80 * 60)
        for iy in range(10, 15):
            for ix in range(10, 20):
                expected[iy * 80 + ix] = 1
        for iy in range(12, 20):
            for ix in range(15, 25):
                expected[iy * 80 + ix] = 2  # painted later: overwrites the overlap
        for iy in range(40, 43):
            for ix in range(60, 63):
                expected[iy * 80 + ix] = 2
        self.assertEqual(labels, expected)
        info = c.get_layer("g", "rooms", statistics=True)
        self.assertEqual(info["labels"], {"1": "kitchen", "2": "hall"})
        self.assertEqual(info["statistics"]["cells_per_label"], {"1": expected.count(1), "2": expected.count(2)})
        self.assertEqual(info["version"], 3)
        # Painting an existing label reuses its id.
        self.assertEqual(c.paint_label("g", "rooms", "kitchen", [rect(7.0, 5.0, 7.2, 5.2)])["label_id"], 1)

    def test_regions_area_and_centroid(self):
        c = self.c
        c.create_layer("g", "surf", {"kind": "probability", "base": "occ"})
        big, small = rect(1.6, 2.6, 2.4, 3.0), rect(2.2, 1.8, 2.4, 2.0)  # 8 x 4 and 2 x 2 cells
        self.observe("surf", [big, small])
        regions = c.regions("g", "surf", threshold=0.6)
        self.assertEqual(regions["version"], 2)
        rs = regions["regions"]
        self.assertEqual([r["cells"] for r in rs], [32, 4])
        self.assertAlmostEqual(rs[0]["area_m2"], 0.32, places=9)
        self.assertAlmostEqual(rs[1]["area_m2"], 0.04, places=9)
        self.assertAlmostEqual(rs[0]["centroid"][0], 2.0, places=6)
        self.assertAlmostEqual(rs[0]["centroid"][1], 2.8, places=6)
        self.assertAlmostEqual(rs[1]["centroid"][0], 2.3, places=6)
        self.assertAlmostEqual(rs[1]["centroid"][1], 1.9, places=6)
        self.assertAlmostEqual(rs[0]["mean_probability"], 0.7, places=5)
        for r, (x0, y0, x1, y1) in zip(rs, [(1.6, 2.6, 2.4, 3.0), (2.2, 1.8, 2.4, 2.0)]):
            self.assertGreaterEqual(len(r["polygon"]), 3)
            for x, y in r["polygon"]:  # through the centres of the boundary cells
                self.assertTrue(x0 < x < x1 and y0 < y < y1, (x, y))
        self.assertEqual([r["cells"] for r in c.regions("g", "surf", threshold=0.6, min_area_m2=0.1)["regions"]], [32])
        self.assertEqual(c.regions("g", "surf", threshold=0.75)["regions"], [])

    def test_unobserved_cells_are_not_a_region_at_the_default_threshold(self):
        """A cell nobody observed has p = 0.5 (unknown). With the default threshold (0.5), regions, attention and
        viewpoints must not treat the whole unobserved map as one surface."""
        c = self.c
        c.create_layer("g", "fresh", {"kind": "probability", "base": "occ"})
        c.put_agent("g", "bystander", [1.0, 1.0], 0.0)
        regions = c.regions("g", "fresh")["regions"]
        self.assertEqual([(r["cells"], r["mean_probability"]) for r in regions], [],
                         "a never-observed layer has regions at the default threshold")
        self.assertFalse(c.attention("g", "bystander", "fresh")["attending"],
                         "attention reports a surface on a never-observed layer")

    def test_deleting_a_layer_others_depend_on_is_a_conflict(self):
        c = self.c
        c.import_occupancy("g", "base2", self.MAP.yaml(), self.MAP.pgm())
        c.create_layer("g", "dep", {"kind": "probability", "base": "base2"})
        c.create_layer("g", "dep2", {"kind": "probability", "base": "base2"})
        c.create_layer("g", "depf", {"kind": "fused", "op": "or", "operands": [{"layer": "dep"}, {"layer": "dep2"}]})
        for layer in ("base2", "dep"):
            with self.assertRaises(ApiError) as cm:
                c.delete_layer("g", layer)
            self.assertEqual((cm.exception.status, cm.exception.code), (409, "conflict"), layer)
            self.assertEqual(cm.exception.field, "layer")
            c.get_layer("g", layer)  # still there
        c.delete_layer("g", "depf")
        c.delete_layer("g", "dep")
        c.delete_layer("g", "dep2")
        c.delete_layer("g", "base2")
        names = [l["name"] for l in c.list_layers("g")["layers"]]
        self.assertFalse({"base2", "dep", "dep2", "depf"} & set(names), names)


if __name__ == "__main__":
    unittest.main()
