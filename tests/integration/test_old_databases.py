"""Database files of earlier releases (tests/data/*.sqlite, SPEC section 8, STYLE habit 7): the current server opens a
copy of each, migrates it to the newest schema, and every entity the old server wrote reads back as the old server
read it (the manifest beside each file, written by tests/data/make_old_database.py).

For every file: after the migration PRAGMA integrity_check is ok, foreign_key_check is empty, user_version and
schema_migrations reached the newest migration of migrations/; each GET of the manifest answers what the old server
answered (a JSON answer may gain fields, never lose or change one; binary answers have the same bytes, PNGs the same
pixels); the instances' labels written before the 0005 label index existed are found by label (instances?label= and
where?label=; since 0026 instance_labels holds the labels themselves); the hashed API tokens still authenticate with
their roles; no AUTOINCREMENT sequence went backwards; and the migrated memory takes new writes (a frame into the
scene left observing, a new labelled instance, a new keyframe id beyond every id handed out before). Files of
schema 0007 and later also hold what those schemas added (tests/data/old_database_later.py): the audit log reads back
entry for entry, a scene's pose covariance, the OctoMap, anchored features with their codebook and classifiers, the
shape model, furniture instances and an object's classification (with its change event from 0016 on) are still
there, and new features get new ids. The file of the newest schema checks that a file this server wrote itself reads
back after a restart.
"""

import glob
import json
import math
import os
import re
import shutil
import sqlite3
import struct
import sys
import unittest

import harness
from anchordb_client import ApiError

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
DATA = os.path.join(ROOT, "tests", "data")
sys.path.insert(0, DATA)
import make_old_database as gen  # noqa: E402  (the reader shared with the generator)

NEWEST = max(int(re.match(r"(\d+)_", os.path.basename(p)).group(1))
             for p in glob.glob(os.path.join(ROOT, "migrations", "sqlite", "*.sql")))


def assert_reads_back(test, old, new, where):
    """`new` holds everything `old` holds: dicts may gain keys, lists keep their length and order, values are equal
    (numbers exactly: both are what the stored row says)."""
    if isinstance(old, dict):
        test.assertIsInstance(new, dict, where)
        for k, v in old.items():
            test.assertIn(k, new, "%s: field '%s' is gone" % (where, k))
            assert_reads_back(test, v, new[k], "%s.%s" % (where, k))
    elif isinstance(old, list):
        test.assertIsInstance(new, list, where)
        test.assertEqual(len(new), len(old), "%s: %d items, the old server had %d" % (where, len(new), len(old)))
        for i, (a, b) in enumerate(zip(old, new)):
            assert_reads_back(test, a, b, "%s[%d]" % (where, i))
    else:
        test.assertEqual(new, old, where)


def layer_probabilities(c, map_id, layer):
    """Per-cell probabilities (cell order) of an occupancy or probability layer, as the server evaluates them for a
    fused layer's operand: occupancy 1 / 0 / 0.5 (occupied / free / unknown by the map_server thresholds in trinary
    mode), probability from log-odds."""
    info = c.get_layer(map_id, layer)
    raw = c.get_layer(map_id, layer, "raw")
    w, h = info["geometry"]["width_cells"], info["geometry"]["height_cells"]
    if info["kind"] == "probability":
        return [1.0 / (1.0 + math.exp(-v)) for v in struct.unpack("<%df" % (w * h), raw)]
    ms = info["map_server"]
    out = []
    for iy in range(h):  # raw occupancy is the image (row 0 at the top); cells count iy from the bottom
        row = raw[(h - 1 - iy) * w:(h - iy) * w]
        for px in row:
            p = (px if ms["negate"] else 255 - px) / 255.0
            out.append(1.0 if p > ms["occupied_thresh"] else 0.0 if p < ms["free_thresh"] else 0.5)
    return out


def and_not_mask(c, map_id, operands, strict):
    """The mask of a fused and_not layer computed here from its operands, with thresholds strict (p > t) or not."""
    masks = [[(p > t if strict else p >= t) for p in layer_probabilities(c, map_id, name)] for name, t in operands]
    return bytes(1 if masks[0][i] and not any(m[i] for m in masks[1:]) else 0 for i in range(len(masks[0])))


def strict_thresholds(test, c, entry, old, new):
    """Commit 0c38885 ("strict thresholds") made a fused operand's threshold strict (p > t; it was p >= t) and renamed
    the statistic cells_at_or_above_0_5 to cells_above_0_5. A fused layer kept from before means what it means today:
    its mask is the strict one, and the old server's mask is the non-strict one of the same operands."""
    m, layer = entry["path"].split("/")[3], entry["path"].split("/")[5].split("?")[0]
    info = c.get_layer(m, layer)
    if entry["path"].endswith("format=raw"):
        operands = [(o["layer"], o["threshold"]) for o in info["operands"]]
        test.assertEqual(info["op"], "and_not")
        test.assertEqual(gen.sha256(and_not_mask(c, m, operands, strict=False)), old["sha256"])
        strict = and_not_mask(c, m, operands, strict=True)
        test.assertEqual(new["sha256"], gen.sha256(strict))
        test.assertNotEqual(new["sha256"], old["sha256"], "the known change no longer shows: drop the exception")
        return
    old = json.loads(json.dumps(old))
    at_or_above = old["statistics"].pop("cells_at_or_above_0_5")
    if info["kind"] == "fused":  # the mask itself changed (above); so did its mean
        cells = list(c.get_layer(m, layer, "raw"))
        old["statistics"].pop("mean_probability")
        test.assertAlmostEqual(new["statistics"]["mean_probability"], sum(cells) / len(cells), places=12)
    else:
        cells = layer_probabilities(c, m, layer)
    assert_reads_back(test, old, new, entry["path"])
    test.assertEqual(new["statistics"]["cells_above_0_5"], sum(1 for p in cells if p > 0.5))
    test.assertGreaterEqual(at_or_above, new["statistics"]["cells_above_0_5"])


# Answers that changed on purpose since a kept file was written: {commit of the file: [(path regex, check)]}. The
# check asserts what the answer is now, instead of the old server's answer.
KNOWN_CHANGES = {
    "164b416": [(r"/layers/unseen_free\?format=raw$", strict_thresholds),
                (r"/layers/(seen|unseen_free)\?format=json&statistics=true$", strict_thresholds)],
}


def serve_copy(manifest, test=None, extra_args=()):
    """The current server on a copy of the kept file (the kept file itself never changes)."""
    server = harness.Server(test, extra_args=extra_args, start=False, sqlite_file=True)
    shutil.copyfile(os.path.join(DATA, manifest["file"]), server.db_path)
    try:
        server.start()
    except BaseException:
        if test is None:
            server.close()
        raise
    return server


class OldDatabase:
    """The tests of one old file; mixed into a TestCase made per file below. The read-only tests share one server
    (setUpClass); a test that writes gets its own copy (fresh())."""

    manifest_path = None

    @classmethod
    def setUpClass(cls):
        with open(cls.manifest_path) as f:
            cls.manifest = json.load(f)
        cls.expect = cls.manifest["expect"]
        cls.server = serve_copy(cls.manifest)
        cls.db = cls.server.db_path
        cls.c = cls.server.client

    def fresh(self, extra_args=()):
        return serve_copy(self.manifest, self, extra_args)

    @classmethod
    def tearDownClass(cls):
        cls.server.close()

    def tearDown(self):
        self.server.check_alive()

    def sql(self, query, *args):
        con = sqlite3.connect("file:%s?mode=ro" % self.db, uri=True)
        try:
            return con.execute(query, args).fetchall()
        finally:
            con.close()

    # ------------------------------------------------------------ the file

    def test_file_migrated_to_newest_schema_and_intact(self):
        old = self.manifest["sqlite"]
        self.assertLessEqual(old["user_version"], NEWEST, "the kept file is of a schema newer than this server's")
        self.assertEqual(self.sql("PRAGMA user_version"), [(NEWEST,)])
        versions = [v for (v,) in self.sql("SELECT version FROM schema_migrations ORDER BY version")]
        self.assertEqual(versions, list(range(1, NEWEST + 1)))
        self.assertEqual(self.sql("PRAGMA integrity_check"), [("ok",)])
        self.assertEqual(self.sql("PRAGMA foreign_key_check"), [])
        # Every index of the newest schema exists (0006 adds instances_by_kind where an early 0005 lacked it).
        indexes = {n for (n,) in self.sql("SELECT name FROM sqlite_master WHERE type = 'index'")}
        self.assertIn("instances_by_kind", indexes)
        # No row was lost on the way (tables the migrations rebuilt included).
        for table, rows in old["rows"].items():
            if table == "schema_migrations":
                continue
            with self.subTest(table=table):
                self.assertEqual(self.sql('SELECT count(*) FROM "%s"' % table), [(rows,)])

    def test_no_autoincrement_sequence_went_backwards(self):
        now = dict(self.sql("SELECT name, seq FROM sqlite_sequence"))
        for table, seq in self.manifest["sqlite"]["sequences"].items():
            with self.subTest(table=table):
                self.assertGreaterEqual(now.get(table, 0), seq, "ids up to %d were handed out in %s" % (seq, table))

    # ------------------------------------------------------------ what the old server wrote

    def test_every_read_of_the_old_server_reads_back(self):
        self.assertGreater(len(self.manifest["reads"]), 20)
        changes = KNOWN_CHANGES.get(self.manifest["commit"], [])
        for entry in self.manifest["reads"]:
            with self.subTest(path=entry["path"]):
                new = gen.read_entry(self.c, entry)
                check = next((f for pattern, f in changes if re.search(pattern, entry["path"])), None)
                if check:
                    check(self, self.c, entry, entry["value"], new)
                else:
                    assert_reads_back(self, entry["value"], new, entry["path"])

    def test_maps_layers_and_agents(self):
        self.assertEqual({m["id"]: m["name"] for m in self.c.list_maps()["maps"]}, self.expect["maps"])
        for key, want in self.expect["layers"].items():
            with self.subTest(layer=key):
                m, name = key.split("/")
                self.assertEqual(self.c.get_layer(m, name)["kind"], want["kind"])
                raw = self.c.get_layer(m, name, "raw")
                self.assertEqual((int(self.c.last_headers["x-grid-width"]), int(self.c.last_headers["x-grid-height"])),
                                 (want["width"], want["height"]))
                if not any(re.search(p, "/v1/maps/%s/layers/%s?format=raw" % (m, name))
                           for p, _ in KNOWN_CHANGES.get(self.manifest["commit"], [])):
                    self.assertEqual(gen.sha256(raw), want["sha256"])
                self.assertGreater(want["distinct_values"], 1, "degenerate layer in the kept file")
        self.assertEqual({k["kind"] for k in self.expect["layers"].values()},
                         {"occupancy", "probability", "fused", "label"})
        for m, agents in self.expect["agents"].items():
            self.assertEqual(sorted(a["id"] for a in self.c.list_agents(m)["agents"]), agents)

    def test_tokens_authenticate_with_their_roles(self):
        tokens = self.manifest["tokens"]
        self.assertEqual(sorted(tokens), ["admin", "reader", "writer"])
        server = self.fresh(["--auth=required"])
        reader, writer = server.make_client(tokens["reader"]), server.make_client(tokens["writer"])
        self.assertIn("home", [m["id"] for m in reader.list_maps()["maps"]])
        with self.assertRaises(ApiError) as e:
            reader.put_agent("home", "carol", [0.1, 0.1], 0.0)
        self.assertEqual(e.exception.status, 403)
        with self.assertRaises(ApiError) as e:
            server.make_client("not-a-token").list_maps()
        self.assertEqual(e.exception.status, 401)
        writer.put_agent("garage", "carol", [0.1, 0.1], 0.0)
        with self.assertRaises(ApiError) as e:
            writer.delete_map("garage")
        self.assertEqual(e.exception.status, 403)
        admin = server.make_client(tokens["admin"])
        self.assertEqual(admin.get_agent("garage", "carol")["position"], [0.1, 0.1])
        admin.delete_map("garage")
        self.assertNotIn("garage", [m["id"] for m in reader.list_maps()["maps"]])


class ScenesOfOldDatabase:
    """Scene models and keyframes (schema 0002 and later)."""

    def test_scenes_and_keyframes(self):
        for sid, status in self.expect["scenes"].items():
            with self.subTest(scene=sid):
                self.assertEqual(self.c.request("GET", "/v1/maps/home/scenes/%s" % sid)["status"], status)
        self.assertIn("closed", self.expect["scenes"].values())
        self.assertIn("observing", self.expect["scenes"].values())
        kinds = set()
        for kid, kind in self.expect["keyframes"].items():
            k = self.c.request("GET", "/v1/maps/home/keyframes/%s" % kid)
            self.assertEqual(k["kind"], kind)
            kinds.add(kind)
        self.assertTrue({"begin", "end", "manual"} <= kinds, kinds)
        # The deleted map's scenes and keyframes are gone with it.
        with self.assertRaises(ApiError) as e:
            self.c.get_map(self.expect["deleted_map"])
        self.assertEqual(e.exception.status, 404)

    def test_migrated_memory_takes_new_frames_and_keyframes(self):
        c = self.fresh().client
        scene = self.expect["observing_scene"]
        view = gen.camera_pose(*self.expect["place_b_pose"]["position"], *self.expect["place_b_view"])
        self.assertEqual(view[0], self.expect["place_b_pose"])
        depth = gen.render_depth(view, [])
        before = c.request("GET", "/v1/maps/home/scenes/%d" % scene)
        self.assertEqual(before["status"], "observing")
        c.request("POST", "/v1/maps/home/scenes/%d/frames?stamp=%d" % (scene, gen.T0_NS + 10 ** 12), depth)
        new_kf = c.request("POST", "/v1/maps/home/scenes/%d/keyframes" % scene)["keyframe"]
        self.assertGreater(new_kf, self.manifest["sqlite"]["sequences"]["keyframes"],
                           "a keyframe id handed out before was given again")
        c.request("POST", "/v1/maps/home/scenes/%d:close" % scene)
        after = c.request("GET", "/v1/maps/home/scenes/%d" % scene)
        self.assertEqual(after["status"], "closed")
        self.assertEqual(after["frames"], before["frames"] + 1)
        self.assertEqual(c.request("GET", "/v1/maps/home/keyframes/%d" % new_kf)["kind"], "manual")


class FurnitureOfOldDatabase:
    """Furniture graphs (schema 0003 and later)."""

    def test_furniture_graphs_with_their_descriptions(self):
        for gid, want in self.expect["furniture_graphs"].items():
            with self.subTest(graph=gid):
                g = self.c.request("GET", "/v1/maps/home/furniture-graphs/%s" % gid)
                self.assertEqual(g["descriptions"], len(want["descriptions"]))
                self.assertEqual(want["count"], len(want["descriptions"]))


class EventsOfOldDatabase:
    """Instances, events, history and jobs (schema 0004 and later); the 0005 label index on pre-0005 rows."""

    def test_instances_events_history_and_jobs(self):
        listed = self.c.request("GET", "/v1/maps/home/instances?limit=1000")["instances"]
        listed += self.c.request("GET", "/v1/maps/home/instances?status=deleted&limit=1000")["instances"]
        instances = {str(i["id"]): i for i in listed}
        self.assertEqual({k: v["labels"] for k, v in instances.items()}, self.expect["instance_labels"])
        self.assertEqual(instances[str(self.expect["deleted_instance"])]["status"], "deleted")
        events = self.c.events("home", limit=1000)["events"]
        counts = {}
        for e in events:
            counts[e["type"]] = counts.get(e["type"], 0) + 1
        self.assertEqual(counts, self.expect["event_counts"])
        self.assertIn("labelled", counts)
        for iid in instances:
            self.assertGreater(len(self.c.history("home", int(iid))["history"]), 0, iid)
        for jid, status in self.expect["jobs"].items():
            self.assertEqual(self.c.job(int(jid))["status"], status)

    def test_label_index_holds_the_instances_written_before_it(self):
        by_label = self.expect["instances_by_label"]
        self.assertTrue({"mug", "table"} <= set(by_label), by_label)
        if self.manifest["sqlite"]["user_version"] < 5:
            self.assertNotIn("instance_labels", self.manifest["sqlite"]["rows"])  # it is the backfill that made it
        indexed = {}
        for iid, label in self.sql("SELECT l.instance_id, l.label FROM instance_labels AS l JOIN instances AS i "
                                   "ON i.id = l.instance_id WHERE i.map_id = 'home'"):
            indexed.setdefault(label, []).append(iid)
        # The index holds the labels instances store; a classifier's (0015) are its distribution, found by
        # instances?label= through instance_classifications instead.
        home = self.c.request("GET", "/v1/maps/home/instances?limit=1000")["instances"]
        by_classifier = {i["id"] for i in home if i.get("label_source") == "classifier"}
        stored = {k: [i for i in v if i not in by_classifier] for k, v in by_label.items()}
        self.assertEqual({k: sorted(v) for k, v in indexed.items()}, {k: v for k, v in stored.items() if v})
        kinds = {i["id"]: i["kind"] for i in home}
        for label, ids in by_label.items():
            live = [i for i in ids if i != self.expect["deleted_instance"]]
            with self.subTest(label=label):
                got = self.c.request("GET", "/v1/maps/home/instances?label=%s&limit=1000" % label)["instances"]
                self.assertEqual(sorted(i["id"] for i in got), live)
                if live and kinds[live[0]] == "object":  # where-is answers for objects
                    self.assertIn(self.c.where("home", label)["instance"], live)

    def test_label_index_follows_writes_after_the_migration(self):
        c = self.fresh().client
        made = c.create_instance("home", "vase", [1.0, 1.0, 0.0], kind="object")
        self.assertEqual([i["id"] for i in c.instances("home", label="vase")["instances"]], [made["id"]])
        mug = self.expect["instances_by_label"]["mug"]
        c.label_instance("home", mug[0], "teapot", source="operator")
        self.assertEqual([i["id"] for i in c.instances("home", label="teapot")["instances"]], mug)
        self.assertEqual(c.instances("home", label="mug")["instances"], [])


class LaterOfOldDatabase:
    """What schemas 0007-0016 added (tests/data/old_database_later.py), each when the old server had its route."""

    def test_audit_log(self):
        if "audit_actions" not in self.expect:
            self.skipTest("no audit log at this schema")
        actions = {}
        for e in self.c.request("GET", "/v1/audit?limit=1000")["entries"]:
            actions[e["action"]] = actions.get(e["action"], 0) + 1
        self.assertEqual(actions, self.expect["audit_actions"])

    def test_scene_pose_covariance(self):
        if "covariance_scene" not in self.expect:
            self.skipTest("no pose covariance at this schema")
        want = self.expect["covariance_scene"]
        scene = self.c.request("GET", "/v1/maps/home/scenes/%d" % want["id"])
        self.assertEqual(scene["pose_covariance"], want["pose_covariance"])

    def test_octomap_features_shape_models_and_furniture(self):
        if "octomap" in self.expect:
            info = self.c.request("GET", "/v1/maps/living/octomap?format=json")
            self.assertEqual(info["leaves"], self.expect["octomap"]["leaves"])
        if "features" in self.expect:
            want = self.expect["features"]
            got = self.c.request("GET", "/v1/maps/home/features?type=%s&limit=1000" % want["type"])["features"]
            self.assertEqual(len(got), want["count"])
            classifiers = self.c.request("GET", "/v1/classifiers")["classifiers"]
            self.assertIn(want["classifier"], [c["name"] for c in classifiers])
        if "shape_model" in self.expect:
            model = self.c.request("GET", "/v1/shape-models/%s" % self.expect["shape_model"]["name"])
            self.assertEqual(model["categories"], self.expect["shape_model"]["categories"])
        if "furniture" in self.expect:
            got = self.c.request("GET", "/v1/maps/living/furniture")["furniture"]
            self.assertEqual(len(got), self.expect["furniture"]["count"])
            self.assertGreater(len(got), 0)

    def test_classified_object(self):
        if "classified" not in self.expect:
            self.skipTest("no instance classification at this schema")
        want = self.expect["classified"]
        instance = self.c.request("GET", "/v1/maps/home/instances/%d" % want["instance"])
        self.assertEqual(instance["classification"]["label"], want["label"])
        self.assertEqual(instance["classification"]["classifier"], "probe")
        if want["event"] is not None:  # the classifier's label is a change event (0016)
            event = self.c.request("GET", "/v1/maps/home/events/%d" % want["event"])
            self.assertEqual((event["type"], event["detection"], event["label"]),
                             ("labelled", "classifier", want["label"]))

    def test_migrated_memory_takes_new_features(self):
        if "features" not in self.expect:
            self.skipTest("no features at this schema")
        c = self.fresh().client
        made = c.request("POST", "/v1/maps/home/features", {"type": self.expect["features"]["type"], "features": [
            {"descriptor": [9.0, 9.0, 9.0, 9.0], "anchor_m": [5.0, 5.0, 1.0]}]})
        self.assertEqual(len(made["ids"]), 1, made)
        self.assertGreater(made["ids"][0], self.manifest["sqlite"]["sequences"]["features"])


class KeptFilesTest(unittest.TestCase):
    def test_each_kept_file_has_its_manifest_and_no_wal(self):
        files = sorted(glob.glob(os.path.join(DATA, "*.sqlite")))
        self.assertGreaterEqual(len(files), 2)
        for path in files:
            with self.subTest(file=os.path.basename(path)):
                self.assertTrue(os.path.exists(os.path.splitext(path)[0] + ".json"))
                self.assertFalse(os.path.exists(path + "-wal"))
                # ~70 tables and indexes of one page each, and the pages the frame journal freed, from 0016 on
                self.assertLess(os.path.getsize(path), 640 * 1024)
        versions = set()
        for path in files:
            with open(os.path.splitext(path)[0] + ".json") as f:
                versions.add(json.load(f)["sqlite"]["user_version"])
        self.assertIn(4, versions, "no pre-0005 file with instances")


def _make_tests():
    for manifest in sorted(glob.glob(os.path.join(DATA, "*.json"))):
        with open(manifest) as f:
            m = json.load(f)
        routes = set(m["routes"])
        bases = [OldDatabase]
        if "POST /v1/maps/{map}/scenes" in routes:
            bases.append(ScenesOfOldDatabase)
        if "POST /v1/maps/{map}/furniture-graphs" in routes:
            bases.append(FurnitureOfOldDatabase)
        if "POST /v1/maps/{map}/instances" in routes:
            bases.append(EventsOfOldDatabase)
        if "GET /v1/audit" in routes:
            bases.append(LaterOfOldDatabase)
        name = "Test_" + os.path.splitext(os.path.basename(manifest))[0]
        globals()[name] = type(name, tuple(bases) + (unittest.TestCase,), {"manifest_path": manifest})


_make_tests()

if __name__ == "__main__":
    unittest.main()
