"""The Python client (clients/python/anchordb_client.py) against the real server: one call of every method,
pagination, filters, ApiError fields and the low-level request()."""

import math
import struct
import time
import unittest

import anchordb_client
import harness
from anchordb_client import ApiError, Client

MAP = harness.SyntheticMap(40, 30, 0.1, origin=(-1.0, -1.0, 0.0), walls=[(20, 1, 20, 15)])
SQUARE = [[0.9, 0.2], [1.2, 0.2], [1.2, 0.5], [0.9, 0.5]]


class PythonClientTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server = harness.Server(None)
        cls.c = Client(cls.server.base_url)  # the plain client, not the harness subclass

    @classmethod
    def tearDownClass(cls):
        cls.server.close()

    def test_every_method(self):
        c = self.c
        self.assertEqual(c.health(), {"status": "ok"})
        self.assertIn("settings", c.settings())
        self.assertIn("paths", c.openapi())
        self.assertIn("# TYPE", c.metrics_text())
        self.assertEqual(c.create_map("cm", "Client map")["name"], "Client map")
        self.assertEqual(c.get_map("cm")["id"], "cm")
        self.assertEqual(c.import_occupancy("cm", "occ", MAP.yaml(), MAP.pgm())["kind"], "occupancy")
        self.assertEqual(c.import_occupancy("cm", "occ_png", MAP.yaml(), MAP.png())["kind"], "occupancy")
        self.assertEqual(c.create_layer("cm", "p", {"kind": "probability", "base": "occ"})["version"], 1)
        self.assertEqual(c.create_layer("cm", "lab", {"kind": "label", "base": "occ"})["kind"], "label")
        r = c.observe("cm", "p", harness.identity_pose(0.5, 0.5), 1.0, 2.0, [SQUARE], stamp="2026-11-22T10:00:00Z")
        self.assertEqual(r["version"], 2)
        self.assertEqual(c.paint_label("cm", "lab", "kitchen", [SQUARE])["label_id"], 1)
        self.assertEqual(len(c.regions("cm", "p", threshold=0.6, min_area_m2=0.01)["regions"]), 1)
        self.assertEqual(sorted(l["name"] for l in c.list_layers("cm")["layers"]), ["lab", "occ", "occ_png", "p"])
        self.assertEqual(c.get_layer("cm", "p")["version"], 2)
        self.assertIn("statistics", c.get_layer("cm", "p", statistics=True))
        raw = c.get_layer("cm", "p", "raw")
        self.assertIsInstance(raw, bytes)
        self.assertEqual(c.last_headers["x-grid-width"], "40")
        self.assertEqual(c.last_headers["x-layer-version"], "2")
        self.assertEqual(len(raw), 40 * 30 * 4)
        self.assertAlmostEqual(max(struct.unpack("<1200f", raw)), math.log(0.7 / 0.3), places=5)
        self.assertTrue(c.get_layer("cm", "occ", "png").startswith(b"\x89PNG"))
        self.assertTrue(c.get_layer("cm", "occ", "pgm").startswith(b"P5"))
        self.assertIn(b"resolution:", c.get_layer("cm", "occ", "yaml"))
        agent = c.put_agent("cm", "ann", [1.0, 0.35], math.pi, velocity=[0.2, 0.0], stamp=1234)
        self.assertEqual((agent["id"], agent["stamp"]), ("ann", 1234))
        c.put_agent("cm", "ben", [2.5, 2.0], 0.0)
        self.assertEqual(c.get_agent("cm", "ann")["velocity"], [0.2, 0.0])
        self.assertEqual(sorted(a["id"] for a in c.list_agents("cm")["agents"]), ["ann", "ben"])
        self.assertEqual([a["id"] for a in c.list_agents("cm", bbox=(0.0, 0.0, 1.5, 1.0))["agents"]], ["ann"])
        self.assertEqual([a["id"] for a in c.list_agents("cm", bbox=(2.0, 1.5, 3.0, 2.5))["agents"]], ["ben"])
        att = c.attention("cm", "ann", "p", threshold=0.6)
        self.assertEqual(att["agent"], "ann")
        vp = c.viewpoints("cm", [0.0, 0.0], "ann", "p", threshold=0.6, max=5)
        self.assertLessEqual(len(vp["viewpoints"]), 5)
        self.assertEqual(c.delete_layer("cm", "lab"), {"deleted": "lab"})
        self.assertEqual(c.delete_map("cm"), {"deleted": "cm"})

    def test_event_methods(self):
        c = self.c
        c.create_map("ev", "Events")
        table = c.create_instance("ev", "Table", [1.0, 2.0, 0.4], extent=[0.8, 1.2, 0.75])
        cup = c.create_instance("ev", "cup", [1.1, 2.1, 0.8], kind="object", extent=[0.08, 0.08, 0.1])
        self.assertEqual(table["labels"], {"table": 1.0})
        self.assertEqual([i["id"] for i in c.instances("ev", kind="object")["instances"]], [cup["id"]])
        relabelled = c.label_instance("ev", cup["id"], "Mug", source="operator")
        self.assertEqual(relabelled["instance"]["labels"], {"mug": 1.0})
        self.assertEqual(relabelled["event"]["type"], "labelled")
        where = c.where("ev", "mug")
        self.assertEqual(where["instance"], cup["id"])
        self.assertEqual(where["sentence"], "The mug is on the table.")
        self.assertEqual(len(c.history("ev", cup["id"])["history"]), 1)
        self.assertEqual([e["type"] for e in c.events("ev", type="labelled")["events"]], ["labelled"])
        with self.assertRaises(ApiError) as err:
            c.label_event("ev", 999, "keys")
        self.assertEqual(err.exception.status, 404)
        job = c.forget("ev", policy={"keyframe_max_age_s": 0}, dry_run=True)
        for _ in range(500):
            state = c.job(job["job"])
            if state["status"] in ("succeeded", "failed"):
                break
            time.sleep(0.01)
        self.assertEqual(state["status"], "succeeded")
        self.assertTrue(state["result"]["dry_run"])
        c.delete_map("ev")

    def test_pagination(self):
        c = self.c
        ids = ["page%02d" % i for i in range(7)]
        for i in ids:
            c.create_map(i)
        seen, cursor = [], None
        while True:
            page = c.list_maps(limit=3, cursor=cursor)
            self.assertLessEqual(len(page["maps"]), 3)
            seen += [m["id"] for m in page["maps"]]
            cursor = page["next_cursor"]
            if cursor is None:
                break
        self.assertEqual([s for s in seen if s.startswith("page")], ids)
        self.assertEqual(len(seen), len(set(seen)))
        for i in ids:
            c.delete_map(i)

    def test_api_error_fields(self):
        with self.assertRaises(ApiError) as cm:
            self.c.observe("nomap", "p", {"position": [0, 0, 0], "orientation": [0, 0, 0, 1]}, 1.0, 1.0, [SQUARE])
        e = cm.exception
        self.assertEqual((e.status, e.code, e.field), (404, "not_found", "map"))
        self.assertIn("nomap", e.message)
        self.assertIn("x-request-id", e.headers)
        with self.assertRaises(ApiError) as cm:
            self.c.create_map("bad id")
        self.assertEqual((cm.exception.status, cm.exception.code, cm.exception.field), (400, "invalid_argument", "id"))

    def test_low_level_request(self):
        r = self.c.request("GET", "/v1/health", raw=True)
        self.assertIsInstance(r, anchordb_client.Response)
        self.assertEqual((r.status, r.json()), (200, {"status": "ok"}))
        r = self.c.request("POST", "/v1/maps", b"{", headers={"Content-Type": "application/json"}, raw=True)
        self.assertEqual(r.status, 400)  # raw=True returns errors instead of raising
        self.assertEqual(self.c.request("POST", "/v1/maps", {"id": "lowlevel"})["id"], "lowlevel")
        self.assertEqual(self.c.request("DELETE", "/v1/maps/lowlevel"), {"deleted": "lowlevel"})

    def test_token_is_sent(self):
        r = Client(self.server.base_url, token="adb_x").request("GET", "/v1/maps", raw=True)
        self.assertEqual(r.status, 200)  # loopback without auth ignores tokens

    def test_connection_refused_raises(self):
        with self.assertRaises(OSError):
            Client("http://127.0.0.1:1", timeout=5).health()


if __name__ == "__main__":
    unittest.main()
