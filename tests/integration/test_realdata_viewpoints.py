"""Acceptance: viewpoints on the AWS house map with a table region and a person. Every returned viewpoint is free,
reachable from the robot, 0.5-2 m from the surface, and the ranking puts 'beside the person' above 'behind the
person'.

The kitchen table's pose comes from aws_small_house/worlds/small_house_model_poses.csv (map frame = world frame)
and its footprint from the bounding box of furniture_converted/table/KitchenTable_01.obj. Observations from four
robot poses around the table, with the footprint as stimulus, make the table a region of a probability layer;
a person stands at the table facing it."""

import collections
import csv
import math
import unittest

import harness

MAP_DIR = "aws_small_house/maps/turtlebot3_waffle_pi"
THRESHOLD = 0.6


def read(*parts):
    with open(harness.shared_data(*parts), "rb") as f:
        return f.read()


def table_pose():
    with open(harness.shared_data("aws_small_house", "worlds", "small_house_model_poses.csv")) as f:
        rows = [r for r in csv.DictReader(f) if r["model"].endswith("KitchenTable_01")]
    assert len(rows) == 1, rows
    r = rows[0]
    return float(r["x"]), float(r["y"]), float(r["yaw"])


def table_half_extents():
    xs, ys = [], []
    for line in read("aws_small_house", "furniture_converted", "table", "KitchenTable_01.obj").decode().splitlines():
        if line.startswith("v "):
            _, x, y, _z = line.split()[:4]
            xs.append(float(x))
            ys.append(float(y))
    return (max(xs) - min(xs)) / 2, (max(ys) - min(ys)) / 2, (max(xs) + min(xs)) / 2, (max(ys) + min(ys)) / 2


class Table:
    def __init__(self):
        self.x, self.y, self.yaw = table_pose()
        self.hx, self.hy, cx, cy = table_half_extents()
        self.cx, self.cy = self.to_world(cx, cy)

    def to_world(self, lx, ly):
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        return self.x + c * lx - s * ly, self.y + s * lx + c * ly

    def footprint(self, margin=0.0):
        hx, hy = self.hx + margin, self.hy + margin
        return [list(self.to_world(sx * hx, sy * hy)) for sx, sy in ((-1, -1), (1, -1), (1, 1), (-1, 1))]

    def contains(self, x, y, margin=0.0):
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        lx, ly = c * (x - self.x) + s * (y - self.y), -s * (x - self.x) + c * (y - self.y)
        return abs(lx) <= self.hx + margin and abs(ly) <= self.hy + margin

    @property
    def area(self):
        return 4 * self.hx * self.hy


class Occupancy:
    """The exported PGM: pixel rows top to bottom; 254 is free in this map."""

    def __init__(self, pgm, yaml_values):
        self.w, self.h, _, self.pixels = harness.parse_pgm(pgm)
        self.res = yaml_values["resolution"]
        self.ox, self.oy = yaml_values["origin"][:2]

    def cell(self, x, y):
        return int(math.floor((x - self.ox) / self.res)), int(math.floor((y - self.oy) / self.res))

    def pixel(self, ix, iy):
        return self.pixels[(self.h - 1 - iy) * self.w + ix]  # image row 0 is the top of the map

    def free(self, x, y):
        ix, iy = self.cell(x, y)
        return 0 <= ix < self.w and 0 <= iy < self.h and self.pixel(ix, iy) == 254

    def bfs_steps(self, start):
        """8-connected breadth-first search over free pixels: steps from `start` (None = unreachable)."""
        w, h = self.w, self.h
        steps = [None] * (w * h)
        sx, sy = start
        steps[sy * w + sx] = 0
        queue = collections.deque([(sx, sy)])
        while queue:
            x, y = queue.popleft()
            d = steps[y * w + x] + 1
            for dx in (-1, 0, 1):
                for dy in (-1, 0, 1):
                    nx, ny = x + dx, y + dy
                    if 0 <= nx < w and 0 <= ny < h and steps[ny * w + nx] is None and self.pixel(nx, ny) == 254:
                        steps[ny * w + nx] = d
                        queue.append((nx, ny))
        return steps


def relative_angle(person_xy, heading, point):
    a = math.atan2(point[1] - person_xy[1], point[0] - person_xy[0]) - heading
    return abs(math.remainder(a, 2 * math.pi))


class ViewpointsOnAwsHouseTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server = harness.Server(None)
        c = cls.c = cls.server.client
        try:
            yaml_bytes = read(MAP_DIR, "map.yaml")
            c.create_map("house")
            c.import_occupancy("house", "occ", yaml_bytes, read(MAP_DIR, "map.pgm"))
            cls.occ = Occupancy(c.get_layer("house", "occ", "pgm"), harness.parse_map_yaml(yaml_bytes))
            cls.table = Table()
            c.create_layer("house", "surface", {"kind": "probability", "base": "occ"})
        except Exception:
            cls.server.close()
            raise
        cls.scene = None

    @classmethod
    def tearDownClass(cls):
        cls.server.close()

    def tearDown(self):
        self.server.check_alive()

    # ---------------------------------------------------------------- the scene, built once

    def observe_table(self):
        t = self.table
        stimulus = [t.footprint()]
        poses = []
        for lx, ly in ((t.hx + 1.6, 0.0), (-t.hx - 1.6, 0.0), (0.0, t.hy + 1.2), (0.0, -t.hy - 1.2)):
            x, y = t.to_world(lx, ly)
            self.assertTrue(self.occ.free(x, y), "observation pose (%.2f, %.2f) is not free" % (x, y))
            poses.append((x, y, math.atan2(t.cy - y, t.cx - x)))
        for _ in range(2):
            for x, y, yaw in poses:
                r = self.c.observe("house", "surface", harness.identity_pose(x, y, yaw), 1.5, 3.5, stimulus)
                self.assertGreater(r["cells_raised"], 0)

    def person_at_table(self, side, distance):
        """A person `distance` m off the table's long side `side` (+1/-1), facing the table."""
        t = self.table
        x, y = t.to_world(side * (t.hx + distance), 0.0)
        heading = math.atan2(t.cy - y, t.cx - x)
        self.c.put_agent("house", "person", [x, y], heading)
        return (x, y), heading

    def build_scene(self):
        """Observes the table, places the person and asks for viewpoints; cached for every test."""
        cls = type(self)
        if cls.scene is not None:
            return cls.scene
        c, t, occ = self.c, self.table, self.occ
        self.observe_table()
        regions = c.regions("house", "surface", threshold=THRESHOLD)["regions"]
        # The table is one large region (small islands enclosed by occupied leg cells may exist beside it).
        table_regions = [r for r in regions if t.contains(*r["centroid"]) and r["area_m2"] > 0.25 * t.area]
        self.assertEqual(len(table_regions), 1, regions)
        region = table_regions[0]
        robot = (4.0, 0.0)
        self.assertTrue(occ.free(*robot))
        # Place the person beside the table, facing it; move them until some viewpoint lies behind them.
        tried = []
        for side, distance in ((-1, 0.45), (-1, 0.35), (-1, 0.55), (1, 0.45), (1, 0.35)):
            person, heading = self.person_at_table(side, distance)
            attention = c.attention("house", "person", "surface", threshold=THRESHOLD)
            plan = c.viewpoints("house", robot, "person", "surface", threshold=THRESHOLD, max=30)
            relations = [v["relation"] for v in plan["viewpoints"]]
            tried.append((person, relations))
            if "behind" in relations and "beside" in relations:
                break
        else:
            self.fail("no placement of the person gives both 'beside' and 'behind' viewpoints: %s" % tried)
        cls.scene = {"region": region, "robot": robot, "person": person, "heading": heading,
                     "attention": attention, "plan": plan}
        return cls.scene

    # ---------------------------------------------------------------- checks

    def test_table_is_a_region(self):
        t, region = self.table, self.build_scene()["region"]
        self.assertLess(math.hypot(region["centroid"][0] - t.cx, region["centroid"][1] - t.cy), 0.25)
        self.assertGreater(region["area_m2"], 0.5 * t.area)
        self.assertLess(region["area_m2"], 1.05 * t.area)
        for x, y in region["polygon"]:
            self.assertTrue(t.contains(x, y, margin=0.1), (x, y))

    def test_person_attends_the_table(self):
        scene = self.build_scene()
        attention, region = scene["attention"], scene["region"]
        self.assertTrue(attention["attending"], attention)
        self.assertEqual(attention["region"]["id"], region["id"])
        self.assertEqual(attention["region"]["centroid"], region["centroid"])
        self.assertLessEqual(attention["distance_m"], 1.0)
        self.assertLessEqual(attention["facing_angle_rad"], math.pi / 4 + 1e-9)

    def test_every_viewpoint_is_free_reachable_and_at_the_right_distance(self):
        scene = self.build_scene()
        t, occ, robot, person, heading = self.table, self.occ, scene["robot"], scene["person"], scene["heading"]
        plan = scene["plan"]
        self.assertEqual(plan["region"]["id"], scene["region"]["id"])
        steps = occ.bfs_steps(occ.cell(*robot))
        vps = plan["viewpoints"]
        self.assertGreaterEqual(len(vps), 3)
        for v in vps:
            x, y = v["position"]
            ix, iy = occ.cell(x, y)
            where = "viewpoint %d at (%.2f, %.2f)" % (v["rank"], x, y)
            self.assertEqual(occ.pixel(ix, iy), 254, where + " is not a free cell")
            self.assertIsNotNone(steps[iy * occ.w + ix], where + " is not reachable from the robot")
            self.assertGreaterEqual(v["surface_distance_m"], 0.5, where)
            self.assertLessEqual(v["surface_distance_m"], 2.0, where)
            self.assertIsInstance(v["travel_distance_m"], float, where)
            self.assertTrue(math.isfinite(v["travel_distance_m"]), where)
            # The path is at least as long as the straight line and as the unconstrained BFS path.
            self.assertGreaterEqual(v["travel_distance_m"] + 1e-6, math.hypot(x - robot[0], y - robot[1]) - occ.res,
                                    where)
            self.assertGreaterEqual(v["travel_distance_m"] + 1e-6, steps[iy * occ.w + ix] * occ.res, where)
            self.assertFalse(t.contains(x, y, margin=0.45), where + " is on or at the table")
            self.assertGreaterEqual(math.hypot(x - person[0], y - person[1]), 0.5, where + " is at the person")
            # The relation matches the angle between the person's heading and the viewpoint.
            angle = relative_angle(person, heading, (x, y))
            self.assertAlmostEqual(v["relative_angle_rad"], angle, delta=1e-3)
            if abs(angle - math.pi / 4) > 1e-3 and abs(angle - 3 * math.pi / 4) > 1e-3:
                want = "in_front" if angle < math.pi / 4 else "behind" if angle > 3 * math.pi / 4 else "beside"
                self.assertEqual(v["relation"], want, where)
            # It looks at the table.
            to_table = math.atan2(t.cy - y, t.cx - x)
            self.assertLess(abs(math.remainder(v["yaw_rad"] - to_table, 2 * math.pi)), 0.3, where)

    def test_ranking_puts_beside_above_behind(self):
        vps = self.build_scene()["plan"]["viewpoints"]
        self.assertEqual([v["rank"] for v in vps], list(range(1, len(vps) + 1)))
        scores = [v["score"] for v in vps]
        self.assertEqual(scores, sorted(scores, reverse=True))
        beside = [v["rank"] for v in vps if v["relation"] == "beside"]
        behind = [v["rank"] for v in vps if v["relation"] == "behind"]
        self.assertLess(max(beside), min(behind), "a 'behind' viewpoint outranks a 'beside' one: %s" % [
            (v["rank"], v["relation"], round(v["score"], 3)) for v in vps])

    def test_position_rating_is_best_beside_and_worst_behind(self):
        """SPEC 4.1 / thesis 3.4.3: the rating by position relative to the person puts beside best and behind
        worst, so every position_score of a 'behind' viewpoint is below every 'in_front' one, and every 'beside'
        one is at least every 'in_front' one."""
        vps = self.build_scene()["plan"]["viewpoints"]
        by = collections.defaultdict(list)
        for v in vps:
            by[v["relation"]].append((round(v["position_score"], 3), round(v["relative_angle_rad"], 2), v["rank"]))
        self.assertTrue(by["in_front"], "no 'in_front' viewpoint to compare with: %s" % dict(by))
        problems = []
        if by["behind"] and max(by["behind"])[0] >= min(by["in_front"])[0]:
            problems.append("behind %s rates at least in_front %s" % (max(by["behind"]), min(by["in_front"])))
        if by["beside"] and min(by["beside"])[0] < max(by["in_front"])[0]:
            problems.append("beside %s rates below in_front %s" % (min(by["beside"]), max(by["in_front"])))
        self.assertEqual(problems, [], "(position_score, relative_angle_rad, rank): %s" % dict(by))


if __name__ == "__main__":
    unittest.main()
