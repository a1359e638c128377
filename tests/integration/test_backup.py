"""Online backup (SPEC section 8): POST /v1/backups queues a job that copies the whole database with SQLite's backup
API while the server keeps serving reads and writes; the copy is restored by serving it, and it answers like the
original did when the backup was taken. `anchordb backup` does the same from cron against a live server's file.
Refusals (bad labels, unknown fields, roles) are clear JSON errors and queue nothing."""

import os
import sqlite3
import struct
import threading
import time
import unittest

import harness
from anchordb_client import ApiError

W, H = 64, 48
CAMERA = {"width": W, "height": H, "fx": 52.5, "fy": 52.5, "cx": 31.5, "cy": 23.5}
MAP = harness.SyntheticMap(40, 30, 0.1, walls=[(20, 1, 20, 15)])


def wait_job(client, job_id, timeout=60):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        job = client.request("GET", "/v1/jobs/%d" % job_id)
        if job["status"] in ("succeeded", "failed"):
            return job
        time.sleep(0.02)
    raise AssertionError("job %d did not finish: %r" % (job_id, job))


def snapshot(client):
    """What a reader sees: maps, the layer bytes, scenes, instances, agents."""
    out = {"maps": client.list_maps(limit=1000)}
    for m in out["maps"]["maps"]:
        mid = m["id"]
        out[mid + "/layers"] = client.list_layers(mid)
        for layer in out[mid + "/layers"]["layers"]:
            out[mid + "/layer/" + layer["name"]] = client.request(
                "GET", "/v1/maps/%s/layers/%s?format=raw" % (mid, layer["name"]), raw=True).body
        out[mid + "/scenes"] = client.request("GET", "/v1/maps/%s/scenes" % mid)
        out[mid + "/instances"] = client.instances(mid)
        out[mid + "/agents"] = client.list_agents(mid)
    return out


class BackupTest(unittest.TestCase):
    def setUp(self):
        self.server = harness.Server(self)
        self.c = c = self.server.client
        c.create_map("home")
        c.import_occupancy("home", "occupancy", MAP.yaml(), MAP.pgm())
        c.create_layer("home", "people", {"kind": "probability", "base": "occupancy"})
        c.observe("home", "people", {"position": [0.5, 0.5, 0.0], "orientation": [0, 0, 0, 1]}, 1.0, 2.0,
                  [[[0.9, 0.2], [1.2, 0.2], [1.2, 0.5], [0.9, 0.5]]])
        c.create_instance("home", "table", [1.0, 1.0, 0.4], extent=[0.8, 1.2, 0.75])
        pose = {"position": [0.0, 0.0, 1.0], "orientation": [0.0, 0.0, 0.0, 1.0]}
        scene = c.request("POST", "/v1/maps/home/scenes", {"camera": CAMERA, "pose": pose})["id"]
        frame = struct.pack("<%dH" % (W * H), *([1500] * (W * H)))
        c.request("POST", "/v1/maps/home/scenes/%d/frames" % scene, frame)
        c.request("POST", "/v1/maps/home/scenes/%d:close" % scene)

    def test_backup_during_writes_restores_to_what_was_acknowledged(self):
        c = self.c
        before = snapshot(c)
        acknowledged, stop = [], threading.Event()

        def write_agents():
            client = self.server.make_client()
            k = 0
            while not stop.is_set():
                client.put_agent("home", "p%d" % k, [1.0, 1.0], 0.0)
                acknowledged.append("p%d" % k)
                k += 1

        writer = threading.Thread(target=write_agents)
        writer.start()
        try:
            while len(acknowledged) < 20:
                time.sleep(0.005)
            acked_before_backup = list(acknowledged)
            job = c.request("POST", "/v1/backups", {"label": "nightly"})
            self.assertEqual(job["kind"], "backup")
            done = wait_job(c, job["job"])
        finally:
            stop.set()
            writer.join()
        self.assertEqual(done["status"], "succeeded", done)
        result = done["result"]
        self.assertEqual(result["integrity"], "ok")
        path = result["file"]
        self.assertTrue(os.path.isfile(path), path)
        self.assertEqual(os.path.dirname(path), os.path.join(self.server.tmpdir, "backups"))
        self.assertEqual(job["request"]["file"], path)  # absolute already in the request
        self.assertTrue(os.path.basename(path).startswith("x-") and path.endswith("-nightly.sqlite"), path)
        self.assertEqual(os.path.getsize(path), result["bytes"])
        self.assertFalse(os.path.exists(path + ".partial"))

        # Restore = serve the copy: it answers like the original did, plus the agents written meanwhile up to the
        # moment of the copy (every one acknowledged before the backup was requested).
        restored = harness.Server(self, db_path=path)
        r = restored.client
        after = snapshot(r)
        agents = {a["id"] for a in after["home/agents"]["agents"]}
        self.assertLessEqual(set(acked_before_backup), agents)
        self.assertLessEqual(agents, set(acknowledged))
        for key, value in before.items():
            if key != "home/agents":
                self.assertEqual(after[key], value, key)
        con = sqlite3.connect(path)
        try:
            self.assertEqual(con.execute("PRAGMA integrity_check").fetchone()[0], "ok")
            self.assertEqual(con.execute("PRAGMA foreign_key_check").fetchall(), [])
        finally:
            con.close()

    def test_cli_backup_of_a_live_file(self):
        out_path = os.path.join(self.server.tmpdir, "cron", "copy.sqlite")
        out = harness.run_cli(["backup", "--db", self.server.db_path, "--out", out_path])
        self.assertEqual(out.returncode, 0, out.stderr)
        self.assertIn('"integrity": "ok"', out.stdout)
        self.assertTrue(os.path.isfile(out_path))
        again = harness.run_cli(["backup", "--db", self.server.db_path, "--out", out_path])
        self.assertEqual(again.returncode, 2, again.stderr)
        self.assertIn("exists", again.stderr)
        bad = harness.run_cli(["backup", "--db", self.server.db_path, "--label", "../etc"])
        self.assertEqual(bad.returncode, 2, bad.stderr)
        self.assertIn("label", bad.stderr)

    def test_refusals_queue_nothing(self):
        c = self.c
        for body, status, field in (({"label": "../../etc/passwd"}, 400, "label"),
                                    ({"label": "x" * 65}, 400, "label"),
                                    ({"label": 7}, 400, "label"),
                                    ({"file": "/tmp/elsewhere.sqlite"}, 400, "file")):
            with self.assertRaises(ApiError) as e:
                c.request("POST", "/v1/backups", body)
            self.assertEqual((e.exception.status, e.exception.field), (status, field), e.exception.message)
        self.assertFalse(os.path.exists(os.path.join(self.server.tmpdir, "backups")))


class RelativeDatabasePathTest(unittest.TestCase):
    def test_backup_file_is_named_absolutely(self):
        # scripts/run serves ./var/anchordb.sqlite: the job must still name its file so a client can find it.
        server = harness.Server(self, db_path="relative.sqlite")  # the server's working directory is its tmpdir
        c = server.client
        job = c.request("POST", "/v1/backups", {})
        self.assertTrue(os.path.isabs(job["request"]["file"]), job)
        done = wait_job(c, job["job"])
        self.assertEqual(done["result"]["file"], job["request"]["file"])
        self.assertEqual(os.path.dirname(done["result"]["file"]), os.path.realpath(os.path.join(server.tmpdir, "backups")))


class BackupRoleTest(unittest.TestCase):
    def test_only_admin_may_back_up(self):
        server = harness.Server(self, start=False)
        secrets = {role: harness.create_token(server.db_path, role) for role in ("reader", "writer", "admin")}
        server.extra_args = ["--auth=required"]
        server.start()
        for role in ("reader", "writer"):
            with self.assertRaises(ApiError) as e:
                server.make_client(secrets[role]).request("POST", "/v1/backups", {})
            self.assertEqual(e.exception.status, 403)
        with self.assertRaises(ApiError) as e:
            server.make_client().request("POST", "/v1/backups", {})
        self.assertEqual(e.exception.status, 401)
        admin = server.make_client(secrets["admin"])
        done = wait_job(admin, admin.request("POST", "/v1/backups", {})["job"])
        self.assertEqual(done["status"], "succeeded", done)


if __name__ == "__main__":
    unittest.main()
