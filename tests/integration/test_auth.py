"""Authentication and roles (SPEC section 8): tokens created with `anchordb token create`, Bearer auth with the
roles reader < writer < admin, refusal to start without tokens where they are required, and denied writes that
change nothing."""

import os
import sqlite3
import unittest

import harness
from anchordb_client import ApiError

MAP = harness.SyntheticMap(30, 20, 0.1, walls=[(15, 1, 15, 10)])
OBS = {"pose": {"position": [0.5, 0.5, 0.0], "orientation": [0, 0, 0, 1]}, "fov_rad": 1.2, "range_m": 1.0,
       "stimulus": [[[0.8, 0.3], [1.1, 0.3], [1.1, 0.7], [0.8, 0.7]]]}


class RefuseToStartTest(unittest.TestCase):
    def setUp(self):
        self.server = harness.Server(self, start=False)  # only for its temporary directory and db path

    def assert_refuses(self, args, words):
        out = harness.run_server_expecting_exit(["--db", self.server.db_path, "--port", "0"] + args)
        self.assertNotEqual(out.returncode, 0, "the server started with %s: %s" % (args, out.stdout))
        self.assertNotIn("listening", out.stdout)
        for word in words:
            self.assertIn(word, out.stderr.lower(), out.stderr)
        return out

    def test_auth_required_without_tokens_exits(self):
        self.assert_refuses(["--auth=required"], ["token"])

    def test_non_loopback_bind_without_tokens_exits(self):
        # The database has no tokens, so the server must stop before it binds anything.
        self.assert_refuses(["--bind", "0.0.0.0"], ["token", "0.0.0.0"])

    def test_non_loopback_bind_with_auth_off_exits(self):
        self.assert_refuses(["--bind", "0.0.0.0", "--auth=off"], ["0.0.0.0"])

    def test_unknown_role_is_refused(self):
        out = harness.run_cli(["token", "create", "--role", "superuser", "--db", self.server.db_path])
        self.assertNotEqual(out.returncode, 0)
        self.assertIn("role", out.stderr)


class RolesTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server, cls.secrets = harness.server_with_tokens()
        cls.anon = cls.server.make_client()
        cls.reader = cls.server.make_client(cls.secrets["reader"])
        cls.writer = cls.server.make_client(cls.secrets["writer"])
        cls.admin = cls.server.make_client(cls.secrets["admin"])

    @classmethod
    def tearDownClass(cls):
        cls.server.close()

    def setUp(self):
        # A fresh map per test, written by the writer.
        self.map = self.id()[-40:].replace(".", "_")
        self.writer.create_map(self.map)
        self.writer.import_occupancy(self.map, "occ", MAP.yaml(), MAP.pgm())
        self.writer.create_layer(self.map, "prob", {"kind": "probability", "base": "occ"})
        self.writer.observe(self.map, "prob", OBS["pose"], OBS["fov_rad"], OBS["range_m"], OBS["stimulus"])
        self.writer.put_agent(self.map, "p", [1.0, 1.0], 0.0)

    def tearDown(self):
        self.server.check_alive()

    def state(self):
        c = self.admin
        out = {"maps": c.list_maps(), "layers": c.list_layers(self.map), "agents": c.list_agents(self.map)}
        for layer in ("occ", "prob"):
            out["raw " + layer] = c.get_layer(self.map, layer, "raw")
        return out

    def assert_error(self, status, code, fn, *args, **kwargs):
        with self.assertRaises(ApiError) as cm:
            fn(*args, **kwargs)
        self.assertEqual((cm.exception.status, cm.exception.code), (status, code), cm.exception)
        return cm.exception

    def test_public_routes_need_no_token(self):
        self.assertEqual(self.anon.health(), {"status": "ok"})
        self.assertIn("paths", self.anon.openapi())

    def test_no_token_is_401(self):
        for fn, args in [(self.anon.list_maps, ()), (self.anon.get_map, (self.map,)), (self.anon.settings, ()),
                         (self.anon.metrics_text, ()), (self.anon.create_map, ("anon",))]:
            with self.subTest(route=fn.__name__):
                self.assert_error(401, "unauthenticated", fn, *args)

    def test_malformed_authorization_is_401(self):
        for header in ["Basic dXNlcjpwYXNz", "Bearer", "Bearer ", "bearer " + self.secrets["admin"],
                       self.secrets["admin"]]:
            with self.subTest(header=header[:12]):
                r = self.anon.request("GET", "/v1/maps", headers={"Authorization": header}, raw=True)
                self.assertEqual(r.status, 401, r.body)
                self.assertEqual(r.json()["error"]["code"], "unauthenticated")

    def test_unknown_token_is_401(self):
        stranger = self.server.make_client("adb_" + "0" * 32)
        self.assert_error(401, "unauthenticated", stranger.list_maps)
        # A known token with one character changed is unknown too.
        secret = self.secrets["admin"]
        altered = self.server.make_client(secret[:-1] + ("0" if secret[-1] != "0" else "1"))
        self.assert_error(401, "unauthenticated", altered.list_maps)

    def test_reader_reads_but_cannot_write(self):
        r = self.reader
        self.assertIn(self.map, [m["id"] for m in r.list_maps()["maps"]])
        self.assertEqual(r.get_layer(self.map, "prob")["version"], 2)
        r.regions(self.map, "prob", threshold=0.6)
        r.attention(self.map, "p", "prob", threshold=0.6)
        self.assertIn("settings", r.settings())
        self.assertIn("anchordb_http_requests_total", r.metrics_text())
        before = self.state()
        denied = [
            (r.create_map, ("by-reader",)),
            (r.create_layer, (self.map, "p2", {"kind": "probability", "base": "occ"})),
            (r.import_occupancy, (self.map, "occ2", MAP.yaml(), MAP.pgm())),
            (r.observe, (self.map, "prob", OBS["pose"], OBS["fov_rad"], OBS["range_m"], OBS["stimulus"])),
            (r.put_agent, (self.map, "p", [2.0, 2.0], 1.0)),
            (r.delete_layer, (self.map, "prob")),
            (r.delete_map, (self.map,)),
        ]
        for fn, args in denied:
            with self.subTest(route=fn.__name__):
                self.assert_error(403, "forbidden", fn, *args)
        self.assertEqual(self.state(), before)

    def test_reader_may_ask_for_viewpoints(self):
        # POST /viewpoints is a query, not a write: a reader gets past auth (to the 404 of the unknown agent).
        self.assert_error(404, "not_found", self.reader.viewpoints, self.map, [0.5, 0.5], "nobody", "prob")

    def test_writer_writes_but_cannot_delete(self):
        w = self.writer
        w.observe(self.map, "prob", OBS["pose"], OBS["fov_rad"], OBS["range_m"], OBS["stimulus"])
        self.assertEqual(w.get_layer(self.map, "prob")["version"], 3)
        before = self.state()
        self.assert_error(403, "forbidden", w.delete_map, self.map)
        self.assert_error(403, "forbidden", w.delete_layer, self.map, "prob")
        self.assertEqual(self.state(), before)

    def test_admin_deletes(self):
        a = self.admin
        self.assertEqual(a.delete_layer(self.map, "prob"), {"deleted": "prob"})
        self.assert_error(404, "not_found", a.get_layer, self.map, "prob")
        self.assertEqual(a.delete_map(self.map), {"deleted": self.map})
        self.assert_error(404, "not_found", a.get_map, self.map)
        self.assertNotIn(self.map, [m["id"] for m in a.list_maps()["maps"]])
        self.assert_error(404, "not_found", a.list_agents, self.map)

    def test_tokens_are_stored_hashed(self):
        files = [self.server.db_path + suffix for suffix in ("", "-wal")
                 if os.path.exists(self.server.db_path + suffix)]
        blob = b""
        for f in files:
            with open(f, "rb") as fh:
                blob += fh.read()
        for role, secret in self.secrets.items():
            self.assertNotIn(secret.encode(), blob, "the %s token is stored in clear text" % role)
        con = sqlite3.connect("file:%s?mode=ro" % self.server.db_path, uri=True)
        try:
            tables = [r[0] for r in con.execute("SELECT name FROM sqlite_master WHERE type='table'")]
        finally:
            con.close()
        self.assertTrue(any("token" in t for t in tables), tables)


if __name__ == "__main__":
    unittest.main()
