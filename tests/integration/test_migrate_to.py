"""`anchordb migrate-to` (issue 30, acceptance 3): the lost-key demo's memory (anchordb-demo against a real server,
the OctoMap fed from its keyframes) moved from its SQLite file into a scratch PostgreSQL 15 database and back into a
new file; a server on each copy answers where-is, lists every event, serves every keyframe's depth bytes and exports
the OctoMap exactly as the server on the original file did. Bad input: clear errors, nothing written."""

import hashlib
import json
import os
import shutil
import subprocess
import tempfile
import time
import unittest

import harness

MAP = "demo"


def snapshot(server):
    """What the acceptance compares: the where-is answer, every event, every keyframe's depth bytes, the OctoMap."""
    c = server.client
    where = c.request("GET", "/v1/maps/%s/where?label=keys" % MAP)
    events, after = [], 0
    while True:
        page = c.request("GET", "/v1/maps/%s/events?limit=1000&after=%d" % (MAP, after))
        events += page["events"]
        if "next_after" not in page:
            break
        after = page["next_after"]
    keyframes = {}
    for scene in c.request("GET", "/v1/maps/%s/scenes" % MAP)["scenes"]:
        detail = c.request("GET", "/v1/maps/%s/scenes/%d" % (MAP, scene["id"]))
        for k in detail["keyframes"]:
            depth = c.request("GET", "/v1/maps/%s/keyframes/%d/depth" % (MAP, k["id"]), raw=True).body
            keyframes[k["id"]] = hashlib.sha256(depth).hexdigest()
    octomap = c.request("GET", "/v1/maps/%s/octomap?format=bt" % MAP, raw=True).body
    return {"where": where, "events": events, "keyframes": keyframes,
            "octomap_sha256": hashlib.sha256(octomap).hexdigest(), "octomap_bytes": len(octomap)}


class MigrateToTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="anchordb-migrate-")
        self.addCleanup(shutil.rmtree, self.tmp, True)
        _, self.pg_uri, _ = harness.pg_scratch(self)

    def migrate(self, target, source):
        return harness.run_cli(["migrate-to", target, "--db", source], timeout=300)

    def serve_snapshot(self, location):
        server = harness.Server(db_path=location)
        try:
            return snapshot(server)
        finally:
            server.close()

    def test_demo_memory_to_postgresql_and_back_is_identical(self):
        original = os.path.join(self.tmp, "robot.sqlite")
        server = harness.Server(db_path=original, extra_args=["--octomap_from_keyframes=true",
                                                              "--octomap_keyframes_per_commit=1"])
        try:
            demo = subprocess.run([os.environ["ANCHORDB_DEMO_BIN"], "--port", str(server.port), "--map", MAP],
                                  capture_output=True, text=True, timeout=300)
            self.assertEqual(demo.returncode, 0, demo.stdout + demo.stderr)
            newest = max(snapshot(server)["keyframes"])
            for _ in range(600):  # the keyframe feed integrates in the background: until it stored the newest one
                tree = server.client.request("GET", "/v1/maps/%s/octomap?format=json" % MAP)
                if tree.get("keyframes_through", 0) >= newest and tree.get("keyframes_uncommitted", 1) == 0:
                    break
                time.sleep(0.1)
            before = snapshot(server)
        finally:
            server.close()
        self.assertEqual(len(before["where"].get("position_m", [])), 3, before["where"])
        self.assertGreater(len(before["events"]), 3)
        self.assertGreater(len(before["keyframes"]), 3)
        self.assertGreater(before["octomap_bytes"], 1000)

        to_pg = self.migrate(self.pg_uri, original)
        self.assertEqual(to_pg.returncode, 0, to_pg.stderr)
        report = json.loads(to_pg.stdout)
        self.assertTrue(report["verified"])
        self.assertIn("migrate-to: table %d/%d" % (len(report["tables"]), len(report["tables"])), to_pg.stderr)
        by_table = {t["table"]: t for t in report["tables"]}
        self.assertEqual(by_table["events"]["rows"], len(before["events"]))
        self.assertGreater(by_table["keyframes"]["blob_bytes"], 0)
        self.assertEqual(self.serve_snapshot(self.pg_uri), before)

        back = os.path.join(self.tmp, "back.sqlite")
        to_file = self.migrate(back, self.pg_uri)
        self.assertEqual(to_file.returncode, 0, to_file.stderr)
        back_report = json.loads(to_file.stdout)
        for t in report["tables"]:  # every table as it left the file (the audit log holds the migration's own entry)
            if t["table"] != "audit_log":
                self.assertIn(t, back_report["tables"])
        self.assertEqual(self.serve_snapshot(back), before)

    def test_bad_input_is_refused_and_writes_nothing(self):
        source = os.path.join(self.tmp, "robot.sqlite")
        server = harness.Server(db_path=source)
        server.client.request("POST", "/v1/maps", {"id": MAP})
        server.close()

        missing = self.migrate(os.path.join(self.tmp, "new.sqlite"), os.path.join(self.tmp, "nowhere.sqlite"))
        self.assertEqual(missing.returncode, 2)
        self.assertIn("no database at", missing.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.tmp, "new.sqlite")))

        existing = self.migrate(source, source)
        self.assertEqual(existing.returncode, 2)
        self.assertIn("the target is the source", existing.stderr)
        other = os.path.join(self.tmp, "other.sqlite")
        open(other, "wb").close()
        exists = self.migrate(other, source)
        self.assertEqual(exists.returncode, 2)
        self.assertIn("exists already", exists.stderr)
        self.assertEqual(os.path.getsize(other), 0)

        no_target = harness.run_cli(["migrate-to", "--db", source])
        self.assertEqual(no_target.returncode, 2)
        self.assertIn("needs a target", no_target.stderr)

        first = self.migrate(self.pg_uri, source)
        self.assertEqual(first.returncode, 0, first.stderr)
        again = self.migrate(self.pg_uri, source)  # the target holds the memory now: refused, nothing added
        self.assertEqual(again.returncode, 3)
        self.assertIn("holds rows already", again.stderr)
        copy = os.path.join(self.tmp, "copy.sqlite")
        check = self.migrate(copy, self.pg_uri)
        self.assertEqual(check.returncode, 0, check.stderr)
        rows = {t["table"]: t["rows"] for t in json.loads(check.stdout)["tables"]}
        self.assertEqual(rows["maps"], 1)
        source_audit = {t["table"]: t["rows"] for t in json.loads(first.stdout)["tables"]}["audit_log"]
        self.assertEqual(rows["audit_log"], source_audit + 1)  # the one migration that ran left its entry

        unreachable = self.migrate("postgresql://postgres@127.0.0.1:1/anchordb?connect_timeout=2", source)
        self.assertEqual(unreachable.returncode, 3)
        self.assertIn("cannot be reached", unreachable.stderr)


if __name__ == "__main__":
    unittest.main()
