"""scripts/pg-scratch (issue 30): a throwaway PostgreSQL 15 on a free loopback port with a socket folder of its own,
never the default cluster on 5432; it serves SQL over TCP on 127.0.0.1 and over its socket, refuses a second start on
the same DIR, and `stop` ends exactly the server it started and removes DIR."""

import os
import shutil
import subprocess
import tempfile
import unittest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
SCRIPT = os.path.join(ROOT, "scripts", "pg-scratch")
PSQL = "/usr/lib/postgresql/15/bin/psql"


def read_env(path):
    with open(path, encoding="utf-8") as f:
        return dict(line.rstrip("\n").split("=", 1) for line in f if "=" in line)


def alive(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    return True


class PgScratchTest(unittest.TestCase):
    def setUp(self):
        self.parent = tempfile.mkdtemp(prefix="anchordb-pg-")
        os.chmod(self.parent, 0o755)  # the server runs as 'postgres' when the tests run as root
        self.addCleanup(shutil.rmtree, self.parent, True)
        self.dir = os.path.join(self.parent, "pg")

    def run_script(self, *args, check=True):
        out = subprocess.run([SCRIPT] + list(args), capture_output=True, text=True, timeout=180)
        if check:
            self.assertEqual(out.returncode, 0, out.stdout + out.stderr)
        return out

    def psql(self, env, sql, via_tcp):
        host = "127.0.0.1" if via_tcp else env["PGHOST"]
        out = subprocess.run([PSQL, "-h", host, "-p", env["PGPORT"], "-U", "postgres", "-d", "anchordb", "-tA",
                              "-v", "ON_ERROR_STOP=1", "-c", sql], capture_output=True, text=True, timeout=60)
        self.assertEqual(out.returncode, 0, out.stderr)
        return out.stdout.strip()

    def start(self):
        uri = self.run_script("start", self.dir).stdout.strip()
        env = read_env(os.path.join(self.dir, "pg.env"))
        pid = int(env["PG_SCRATCH_PID"])
        self.addCleanup(lambda: os.path.exists(self.dir) and self.run_script("stop", self.dir, check=False))
        return uri, env, pid

    def test_serves_sql_on_its_own_port_and_socket_and_stop_removes_everything(self):
        uri, env, pid = self.start()
        self.assertNotEqual(env["PGPORT"], "5432")
        self.assertEqual(uri, "postgresql://postgres@127.0.0.1:%s/anchordb" % env["PGPORT"])
        self.assertTrue(alive(pid))
        self.assertTrue(env["PGHOST"].startswith(self.dir), env["PGHOST"])
        self.psql(env, "CREATE TABLE t (id bigint PRIMARY KEY, b bytea)", via_tcp=True)
        self.psql(env, "INSERT INTO t VALUES (1, '\\x00ff'::bytea)", via_tcp=False)
        self.assertEqual(self.psql(env, "SELECT encode(b, 'hex') FROM t WHERE id = 1", via_tcp=True), "00ff")
        self.assertEqual(self.psql(env, "SHOW listen_addresses", via_tcp=True), "127.0.0.1")
        self.run_script("stop", self.dir)
        self.assertFalse(alive(pid), "the postmaster still runs after stop")
        self.assertFalse(os.path.exists(self.dir), "stop left %s behind" % self.dir)
        self.assertEqual(os.listdir(self.parent), [])

    def test_a_second_start_on_the_same_dir_is_refused_and_keeps_the_first_server(self):
        _, env, pid = self.start()
        out = self.run_script("start", self.dir, check=False)
        self.assertNotEqual(out.returncode, 0)
        self.assertIn("already", out.stderr)
        self.assertTrue(alive(pid))
        self.assertEqual(self.psql(env, "SELECT 1", via_tcp=True), "1")

    def test_stop_without_a_server_says_so(self):
        out = self.run_script("stop", self.dir, check=False)
        self.assertNotEqual(out.returncode, 0)
        self.assertIn("nothing started", out.stderr)

    def test_bad_usage_is_refused(self):
        out = self.run_script("restart", self.dir, check=False)
        self.assertEqual(out.returncode, 2)
        self.assertIn("usage", out.stderr)


if __name__ == "__main__":
    unittest.main()
