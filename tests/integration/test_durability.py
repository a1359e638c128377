"""Durability (SPEC section 8): a clean restart returns byte-identical layers; after kill -9 in the middle of a stream
of acknowledged writes the file passes PRAGMA integrity_check and every acknowledged update is still there."""

import math
import shutil
import sqlite3
import subprocess
import threading
import unittest

import harness
from anchordb_client import ApiError

MAP = harness.SyntheticMap(60, 40, 0.1, origin=(-1.0, -2.0, 0.0), walls=[(25, 5, 25, 30)], unknown=[(45, 25, 58, 38)])
FORMATS = ("json", "raw", "png", "pgm", "yaml")


def rect(x0, y0, x1, y1):
    return [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]


def integrity_check(db_path):
    """PRAGMA integrity_check through the sqlite3 CLI when installed, and through Python's sqlite3 module."""
    results = []
    if shutil.which("sqlite3"):
        out = subprocess.run(["sqlite3", db_path, "PRAGMA integrity_check"], capture_output=True, text=True, timeout=60)
        results.append(("sqlite3 cli", out.stdout.strip() + out.stderr.strip()))
    con = sqlite3.connect(db_path)
    try:
        results.append(("python sqlite3", "; ".join(r[0] for r in con.execute("PRAGMA integrity_check"))))
        results.append(("foreign keys", str(con.execute("PRAGMA foreign_key_check").fetchall())))
    finally:
        con.close()
    return results


class DurabilityTest(unittest.TestCase):
    def setUp(self):
        self.server = harness.Server(self)
        self.c = self.server.client

    def populate(self):
        c = self.c
        c.create_map("home", "durability")
        c.create_map("other")
        c.import_occupancy("home", "occ", MAP.yaml(), MAP.pgm())
        c.create_layer("home", "surface", {"kind": "probability", "base": "occ"})
        c.create_layer("home", "chairs", {"kind": "probability", "base": "occ",
                                          "log_odds": {"hit": 0.8, "miss": 0.3, "clamp_min": 0.1, "clamp_max": 0.9}})
        c.create_layer("home", "rooms", {"kind": "label", "base": "occ", "labels": {"1": "kitchen"}})
        c.create_layer("home", "both", {"kind": "fused", "op": "and_not",
                                        "operands": [{"layer": "surface", "threshold": 0.6}, {"layer": "chairs"}]})
        for k in range(5):
            yaw = 0.2 * k - 0.4
            c.observe("home", "surface", harness.identity_pose(0.0, -0.5 + 0.1 * k, yaw), 1.2, 3.0,
                      [rect(0.5, -1.0, 1.2, 0.0), rect(0.8, 0.5, 1.3, 0.9)])
            c.observe("home", "chairs", harness.identity_pose(0.2, 0.0, -yaw), 1.5, 2.5, [rect(0.4, -0.4, 0.9, 0.2)])
        c.paint_label("home", "rooms", "kitchen", [rect(-0.5, -1.5, 1.0, 0.0)])
        c.paint_label("home", "rooms", "hall", [rect(2.0, -1.0, 3.5, 1.5)])
        c.put_agent("home", "alice", [0.9, -0.2], 1.0, velocity=[0.1, 0.0], stamp="2026-11-22T10:00:00.5Z")
        c.put_agent("home", "bob", [3.0, 1.0], -2.0)

    def snapshot(self):
        c = self.c
        state = {"maps": c.list_maps(), "home": c.get_map("home"), "other": c.get_map("other"),
                 "layers": c.list_layers("home"), "agents": c.list_agents("home"),
                 "regions": c.regions("home", "surface", threshold=0.6),
                 "attention": c.attention("home", "alice", "surface", threshold=0.6)}
        for layer in state["layers"]["layers"]:
            for fmt in FORMATS:
                key = "%s?format=%s" % (layer["name"], fmt)
                try:
                    state[key] = c.get_layer("home", layer["name"], fmt)
                    if fmt != "json":
                        state[key + " headers"] = {k: v for k, v in c.last_headers.items()
                                                   if k.startswith("x-") and k != "x-request-id"}
                except ApiError as e:
                    state[key] = ("error", e.status, e.code)
            state[layer["name"] + " statistics"] = c.get_layer("home", layer["name"], statistics=True)
        return state

    def test_clean_restart_returns_identical_layers(self):
        self.populate()
        before = self.snapshot()
        self.assertEqual(len(before["layers"]["layers"]), 5)
        self.assertEqual(self.server.stop(), 0, self.server.stderr_text())
        self.server.start()
        self.c = self.server.client
        after = self.snapshot()
        changed = sorted(k for k in set(before) | set(after) if before.get(k) != after.get(k))
        self.assertEqual(changed, [], "differs after a restart")
        self.assertEqual([r[1] for r in integrity_check(self.server.db_path)][-2:], ["ok", "[]"])
        # Writes continue from the stored version.
        r = self.c.observe("home", "surface", harness.identity_pose(0.0, 0.0), 1.0, 2.0, [rect(0.5, -0.2, 0.8, 0.2)])
        self.assertEqual(r["version"], before["surface?format=json"]["version"] + 1)

    def test_kill_9_loses_no_acknowledged_write(self):
        c = self.c
        c.create_map("home")
        c.import_occupancy("home", "occ", MAP.yaml(), MAP.pgm())
        layers = ["stream0", "stream1"]
        for layer in layers:
            c.create_layer("home", layer, {"kind": "probability", "base": "occ"})
        acked = {layer: 1 for layer in layers}
        acked_agent = {"x": None}
        sent = {layer: 0 for layer in layers}
        errors = {}
        enough = threading.Event()
        stop = threading.Event()
        lock = threading.Lock()

        def observations(layer, index):
            client = self.server.make_client(timeout=10)
            k = 0
            while not stop.is_set():
                k += 1
                yaw = math.sin(k * 0.37 + index)
                try:
                    with lock:
                        sent[layer] += 1
                    r = client.observe("home", layer, harness.identity_pose(0.5, 0.0, yaw), 1.4, 3.0,
                                       [rect(1.0 + 0.01 * (k % 30), -0.5, 1.6, 0.3 + 0.01 * (k % 7))])
                except Exception as e:  # the kill: connection refused or reset
                    errors[layer] = repr(e)
                    return
                with lock:
                    if r["version"] <= acked[layer]:
                        errors[layer] = "version went backwards: %d after %d" % (r["version"], acked[layer])
                        return
                    acked[layer] = r["version"]
                    if min(acked.values()) >= 40:
                        enough.set()

        def agents():
            client = self.server.make_client(timeout=10)
            k = 0
            while not stop.is_set():
                k += 1
                try:
                    client.put_agent("home", "walker", [0.01 * (k % 300), 0.5], 0.0, stamp=k)
                except Exception as e:
                    errors["agent"] = repr(e)
                    return
                with lock:
                    acked_agent["x"] = k

        threads = [threading.Thread(target=observations, args=(layer, i)) for i, layer in enumerate(layers)]
        threads.append(threading.Thread(target=agents))
        for t in threads:
            t.start()
        try:
            self.assertTrue(enough.wait(timeout=30), "the writers did not get 40 acknowledgements each in 30 s: %s"
                            % errors)
            self.server.kill()  # mid-stream: the writers are still sending
        finally:
            stop.set()
            for t in threads:
                t.join(timeout=30)
        self.assertFalse(any(t.is_alive() for t in threads))
        self.assertFalse(any("backwards" in e for e in errors.values()), errors)
        # Every writer was still writing when the server died (its next request failed).
        self.assertEqual(set(errors), set(layers) | {"agent"}, errors)
        last_acked = dict(acked)
        last_agent = acked_agent["x"]

        for name, result in integrity_check(self.server.db_path):
            self.assertIn(result, ("ok", "[]"), "%s after kill -9: %s" % (name, result))

        self.server.start()
        c = self.server.client
        for layer in layers:
            info = c.get_layer("home", layer)
            # Every acknowledged update is there; at most the one request in flight at the kill may be too.
            self.assertGreaterEqual(info["version"], last_acked[layer], layer)
            self.assertLessEqual(info["version"], last_acked[layer] + 1, layer)
            self.assertEqual(info["observations"], info["version"] - 1, layer)
            raw = c.get_layer("home", layer, "raw")
            self.assertEqual(len(raw), MAP.width * MAP.height * 4)
        stamp = c.get_agent("home", "walker")["stamp"]
        self.assertGreaterEqual(stamp, last_agent)
        self.assertLessEqual(stamp, last_agent + 1)
        # The restarted server keeps writing from there.
        r = c.observe("home", "stream0", harness.identity_pose(0.5, 0.0), 1.0, 2.0, [rect(1.0, -0.2, 1.3, 0.2)])
        self.assertEqual(r["version"], c.get_layer("home", "stream0")["version"])
        self.assertEqual(self.server.stop(), 0)
        for name, result in integrity_check(self.server.db_path):
            self.assertIn(result, ("ok", "[]"), "%s after a clean stop: %s" % (name, result))


if __name__ == "__main__":
    unittest.main()
