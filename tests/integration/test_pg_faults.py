"""Faults of a PostgreSQL database under a running server (issue 30): the database server stopped (kill of its
postmaster's children by `pg_ctl stop -m immediate`, as a crash) while four clients write; a statement timeout; a
unique violation. Every request in between gets 503 with Retry-After, none 500; every acknowledged write is there
once the database is back; the server is never restarted."""

import os
import subprocess
import threading
import time
import unittest
import urllib.parse

import harness

PG_BIN = "/usr/lib/postgresql/15/bin"


def as_server_user(args):
    return (["runuser", "-u", "postgres", "--"] if os.getuid() == 0 else []) + args


class PgFaultsTest(unittest.TestCase):
    def setUp(self):
        self.pg_dir, self.uri, self.env = harness.pg_scratch(self)

    def pg_ctl(self, *args):
        data = os.path.join(self.pg_dir, "data")
        out = subprocess.run(as_server_user([PG_BIN + "/pg_ctl", "-D", data, "-l", data + "/server.log", "-w",
                                             "-t", "60"] + list(args)), capture_output=True, text=True, timeout=120)
        self.assertEqual(out.returncode, 0, out.stdout + out.stderr)

    def psql(self, sql):
        return subprocess.Popen(as_server_user([PG_BIN + "/psql", "-h", self.env["PGHOST"], "-p", self.env["PGPORT"],
                                                "-U", "postgres", "-d", "anchordb", "-tA", "-v", "ON_ERROR_STOP=1",
                                                "-c", sql]), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)

    def all_maps(self, client):
        ids, cursor = set(), ""
        while True:
            page = client.request("GET", "/v1/maps?limit=500" + ("&cursor=" + urllib.parse.quote(cursor) if cursor else ""))
            ids |= {m["id"] for m in page["maps"]}
            cursor = page.get("next_cursor")
            if not cursor:
                return ids

    def test_database_stopped_under_write_load_loses_no_acknowledged_write(self):
        server = harness.Server(test=self, db_path=self.uri)
        acked, answered_503, bad = set(), [], []
        lock = threading.Lock()
        stop = threading.Event()

        def writer(w):
            client = server.make_client(timeout=60)
            i = 0
            while not stop.is_set():
                map_id = "w%d-%d" % (w, i)
                r = client.request("POST", "/v1/maps", {"id": map_id}, raw=True)
                with lock:
                    if r.status == 201:
                        acked.add(map_id)
                        i += 1
                    elif r.status == 503 and r.headers.get("retry-after"):
                        answered_503.append(map_id)
                        i += 1  # the id may or may not have been written: not reused, not counted as acknowledged
                    else:
                        bad.append((map_id, r.status, r.body[:300]))
                if r.status == 503:
                    time.sleep(0.05)

        threads = [threading.Thread(target=writer, args=(w,)) for w in range(4)]
        for t in threads:
            t.start()
        try:
            def wait_for(condition, what):
                for _ in range(1200):
                    with lock:
                        if condition():
                            return
                    time.sleep(0.05)
                self.fail("waited 60 s for %s (acked %d, 503 %d, bad %s)" % (what, len(acked), len(answered_503), bad[:3]))

            wait_for(lambda: len(acked) >= 40, "40 acknowledged writes")
            self.pg_ctl("-m", "immediate", "stop")  # as a crash: no checkpoint, sessions cut
            wait_for(lambda: len(answered_503) >= 8, "503 answers while the database is down")
            acked_while_down = len(acked)
            self.pg_ctl("start", "-o", "-p %s -k %s -c listen_addresses=127.0.0.1 -c max_connections=200" % (
                self.env["PGPORT"], self.env["PGHOST"]))
            wait_for(lambda: len(acked) >= acked_while_down + 40, "40 writes acknowledged after the restart")
        finally:
            stop.set()
            for t in threads:
                t.join(120)
        self.assertEqual(bad, [], "answers other than 201 or 503 with Retry-After")
        # Reader sessions idle since before the crash are replaced on their first use, not answered 503.
        for _ in range(8):
            r = server.client.request("GET", "/v1/maps?limit=1", raw=True)
            self.assertEqual(r.status, 200, r.body)
        stored = self.all_maps(server.client)
        self.assertEqual(acked - stored, set(), "acknowledged writes missing after the database came back")
        print("acknowledged %d, answered 503 %d, stored %d" % (len(acked), len(answered_503), len(stored)))

    def test_statement_timeout_is_503_and_unique_violation_is_409(self):
        # statement_timeout 300 ms on the server's sessions (libpq's options parameter); the lock wait (lock_timeout =
        # busy_timeout_ms) is longer, so the statement timeout is what ends a wait on a locked table.
        uri = self.uri + "?options=" + urllib.parse.quote("-c statement_timeout=300")
        server = harness.Server(test=self, db_path=uri, extra_args=["--busy_timeout_ms=20000"])
        c = server.client
        c.request("POST", "/v1/maps", {"id": "home"})
        duplicate = c.request("POST", "/v1/maps", {"id": "home"}, raw=True)
        self.assertEqual(duplicate.status, 409, duplicate.body)
        self.assertEqual(duplicate.json()["error"]["code"], "conflict")

        holder = self.psql("BEGIN; LOCK TABLE maps IN ACCESS EXCLUSIVE MODE; SELECT pg_sleep(4); COMMIT;")
        try:
            for _ in range(200):  # until the lock is held
                probe = self.psql("SELECT count(*) FROM pg_locks WHERE relation = 'maps'::regclass AND granted "
                                  "AND mode = 'AccessExclusiveLock'")
                if probe.communicate(timeout=30)[0].strip() == "1":
                    break
                time.sleep(0.05)
            read = c.request("GET", "/v1/maps", raw=True)
            write = c.request("POST", "/v1/maps", {"id": "attic"}, raw=True)
        finally:
            holder.communicate(timeout=60)
        for r in (read, write):
            self.assertEqual(r.status, 503, r.body)
            self.assertTrue(r.headers.get("retry-after"), r.headers)
        self.assertEqual(self.all_maps(c), {"home"}, "the timed-out write left nothing")
        self.assertEqual(c.request("POST", "/v1/maps", {"id": "attic"}, raw=True).status, 201)


if __name__ == "__main__":
    unittest.main()
