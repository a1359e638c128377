"""The audit trail (SPEC section 8: operator and admin actions are audited, who, what, when, before / after) over
the real binary with auth on: GET /v1/audit (admin) shows the token, the action, the time, the request id, the
status and the changed record before and after, for a relabel, a pin, a deletion, a forgetting and a backup;
readers and writers get 403; the filters select what they name. Also: secrets are matched by their id part and
secrets of the earlier form (no id part) still work."""

import hashlib
import sqlite3
import time
import unittest

import harness
from anchordb_client import ApiError


def wait_job(client, job_id, timeout=60):
    deadline = time.time() + timeout
    while time.time() < deadline:
        job = client.job(job_id)
        if job["status"] in ("succeeded", "failed"):
            return job
        time.sleep(0.05)
    raise AssertionError("job %d did not finish" % job_id)


class AuditTest(unittest.TestCase):
    LEGACY_SECRET = "adb_" + "5e" * 16  # the form of secrets made before they carried their id

    @classmethod
    def setUpClass(cls):
        def add_legacy_token(db_path):
            con = sqlite3.connect(db_path)
            with con:
                con.execute("INSERT INTO tokens (id, sha256_hex, role, created_ns) VALUES (?, ?, ?, ?)",
                            ("tok_legacy", hashlib.sha256(cls.LEGACY_SECRET.encode()).hexdigest(), "admin", 1))
            con.close()
        cls.server, cls.secrets = harness.server_with_tokens(before_start=add_legacy_token)
        cls.ids = {role: "tok_" + secret[4:12] for role, secret in cls.secrets.items()}
        cls.reader, cls.writer, cls.admin = (cls.server.make_client(cls.secrets[r]) for r in ("reader", "writer", "admin"))

    @classmethod
    def tearDownClass(cls):
        cls.server.close()

    def setUp(self):
        self.map = self.id().split(".")[-1][-40:]
        self.writer.create_map(self.map)

    def tearDown(self):
        self.server.check_alive()

    def audit(self, **query):
        q = "&".join("%s=%s" % kv for kv in query.items())
        return self.admin.request("GET", "/v1/audit" + ("?" + q if q else ""))

    def entries(self, action):
        return self.audit(map=self.map, action=action)["entries"]

    def test_token_secrets_carry_their_id_and_creation_is_audited(self):
        for role, secret in self.secrets.items():
            self.assertRegex(secret, r"^adb_[0-9a-f]{8}_[0-9a-f]{32}$")
        created = self.audit(action="token.create")["entries"]
        self.assertEqual(sorted((e["resource"], e["after"]["role"]) for e in created),
                         sorted((self.ids[r], r) for r in self.secrets))
        for e in created:
            self.assertEqual(e["actor"], {"token": "cli", "role": None})
            self.assertNotIn("secret", e["after"])

    def test_legacy_secret_still_authenticates(self):
        legacy = self.server.make_client(self.LEGACY_SECRET)
        self.assertIn("maps", legacy.list_maps())
        # One character off, and a well-formed new-style secret naming a real id with a wrong secret part: 401.
        for secret in (self.LEGACY_SECRET[:-1] + "0", self.secrets["admin"][:13] + "0" * 32):
            with self.assertRaises(ApiError) as cm:
                self.server.make_client(secret).list_maps()
            self.assertEqual(cm.exception.status, 401)

    def test_relabel_records_who_what_when_before_after(self):
        inst = self.writer.create_instance(self.map, "table", [1.0, 2.0, 0.0])
        t0 = time.time_ns()
        self.writer.request("POST", "/v1/maps/%s/instances/%d:label" % (self.map, inst["id"]),
                            {"label": "desk", "source": "operator"}, headers={"X-Request-Id": "relabel-1"})
        t1 = time.time_ns()
        [e] = self.entries("instance.label")
        self.assertEqual(e["actor"], {"token": self.ids["writer"], "role": "writer"})
        self.assertEqual((e["map"], e["resource"], e["request_id"], e["status"]),
                         (self.map, "instance=%d" % inst["id"], "relabel-1", 200))
        self.assertTrue(t0 <= e["time_ns"] <= t1, (t0, e["time_ns"], t1))
        self.assertTrue(e["time"].startswith(time.strftime("%Y-%m-%dT", time.gmtime(e["time_ns"] / 1e9))), e["time"])
        self.assertIn("table", e["before"]["labels"])
        self.assertNotIn("desk", e["before"]["labels"])
        self.assertIn("desk", e["after"]["labels"])
        self.assertTrue(e["after"]["label_locked"])
        [created] = self.entries("instance.create")
        self.assertEqual(created["after"]["id"], inst["id"])

    def test_pin_unpin_and_delete(self):
        inst = self.writer.create_instance(self.map, "shelf", [0.0, 1.0, 0.0])
        path = "/v1/maps/%s/instances/%d" % (self.map, inst["id"])
        self.writer.request("POST", path + ":pin")
        self.writer.request("POST", path + ":unpin")
        self.admin.request("DELETE", path)
        [pin] = self.entries("instance.pin")
        self.assertEqual((pin["before"]["pinned"], pin["after"]["pinned"]), (False, True))
        [unpin] = self.entries("instance.unpin")
        self.assertEqual((unpin["before"]["pinned"], unpin["after"]["pinned"]), (True, False))
        [deleted] = self.entries("instance.delete")
        self.assertEqual(deleted["actor"], {"token": self.ids["admin"], "role": "admin"})
        self.assertEqual((deleted["before"]["status"], deleted["after"]["status"]), ("present", "deleted"))

    def test_failed_edit_is_recorded_with_its_status(self):
        with self.assertRaises(ApiError):
            self.writer.request("POST", "/v1/maps/%s/instances/999999:pin" % self.map)
        [e] = self.entries("instance.pin")
        self.assertEqual((e["status"], e["before"], e["after"]), (404, None, None))

    def test_forget_dry_run_and_backup(self):
        job = self.admin.forget(self.map, policy={"keyframe_max_age_s": 0}, dry_run=True)
        wait_job(self.admin, job["job"])
        [f] = self.entries("map.forget")
        self.assertEqual((f["status"], f["after"]["job"], f["actor"]["role"]), (202, job["job"], "admin"))
        backup = self.admin.request("POST", "/v1/backups", {"label": "audit"})
        wait_job(self.admin, backup["job"])
        b = [e for e in self.audit(action="backup.create")["entries"] if e["after"].get("job") == backup["job"]]
        self.assertEqual(len(b), 1)
        self.assertEqual((b[0]["map"], b[0]["status"]), (None, 202))
        # Forgetting by policy (not a dry run) keeps the audit entries.
        count = len(self.audit(map=self.map)["entries"])
        job = self.admin.forget(self.map, policy={"keyframe_max_age_s": 0, "event_max_age_s": 0})
        self.assertEqual(wait_job(self.admin, job["job"])["status"], "succeeded")
        self.assertGreater(len(self.audit(map=self.map)["entries"]), count)

    def test_command_line_forget_and_backup_are_audited(self):
        out = harness.run_cli(["forget", "--db", self.server.db_path, "--map", self.map, "--dry-run"])
        self.assertEqual(out.returncode, 0, out.stderr)
        [f] = self.audit(map=self.map, action="map.forget", actor="cli")["entries"]
        self.assertEqual((f["actor"], f["status"], f["request_id"]), ({"token": "cli", "role": None}, 0, None))
        self.assertIn("dry_run", f["after"])
        count = len(self.audit(action="backup.create", actor="cli")["entries"])
        out = harness.run_cli(["backup", "--db", self.server.db_path, "--label", self.map[:20]])
        self.assertEqual(out.returncode, 0, out.stderr)
        self.assertEqual(len(self.audit(action="backup.create", actor="cli")["entries"]), count + 1)

    def test_map_deletion_keeps_its_entries(self):
        self.admin.delete_map(self.map)
        [e] = self.entries("map.delete")
        self.assertEqual((e["before"]["id"], e["after"]), (self.map, None))

    def test_every_admin_write_is_audited_reads_and_robot_writes_are_not(self):
        self.admin.get_map(self.map)
        self.writer.put_agent(self.map, "p", [1.0, 1.0], 0.0)
        self.admin.put_agent(self.map, "q", [2.0, 1.0], 0.0)
        got = self.audit(map=self.map)["entries"]
        self.assertEqual([e["action"] for e in got], ["PUT /v1/maps/{map}/agents/{agent}"])
        self.assertEqual(got[0]["resource"], "agent=q")

    def test_readers_and_writers_get_403(self):
        for client in (self.reader, self.writer):
            with self.assertRaises(ApiError) as cm:
                client.request("GET", "/v1/audit")
            self.assertEqual((cm.exception.status, cm.exception.code), (403, "forbidden"))

    def test_filters_and_pages(self):
        a = self.writer.create_instance(self.map, "a", [0.0, 0.0, 0.0])
        self.writer.request("POST", "/v1/maps/%s/instances/%d:pin" % (self.map, a["id"]))
        mid = time.time_ns()
        self.admin.request("POST", "/v1/maps/%s/instances/%d:unpin" % (self.map, a["id"]))
        self.assertEqual([e["action"] for e in self.audit(map=self.map, until=mid)["entries"]],
                         ["instance.create", "instance.pin"])
        self.assertEqual([e["action"] for e in self.audit(map=self.map, since=mid)["entries"]], ["instance.unpin"])
        self.assertEqual([e["action"] for e in self.audit(map=self.map, actor=self.ids["writer"])["entries"]],
                         ["instance.create", "instance.pin"])
        first = self.audit(map=self.map, limit=2)
        self.assertEqual(len(first["entries"]), 2)
        rest = self.audit(map=self.map, limit=2, after=first["next_after"])
        self.assertEqual([e["action"] for e in first["entries"] + rest["entries"]],
                         ["instance.create", "instance.pin", "instance.unpin"])
        for query, field in (({"limit": 0}, "limit"), ({"since": "yesterday"}, "since"), ({"actor": "x" * 65}, "actor")):
            with self.assertRaises(ApiError) as cm:
                self.audit(**query)
            self.assertEqual(cm.exception.field, field, query)


if __name__ == "__main__":
    unittest.main()
