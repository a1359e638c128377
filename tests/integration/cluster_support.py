"""A site cluster from ./scripts/cluster (issue 31) for the integration tests and the failover campaign.

    cluster = Cluster(servers=1)          # scripts/cluster up <tmpdir>/c --servers 1 (ANCHORDB_BIN)
    cluster.info                          # DIR/cluster.json
    cluster.leader()                      # the Patroni member that leads: {"name": "node2", "port": ..., ...}
    cluster.kill_leader()                 # kill -9 of the leader's postmaster and of its Patroni
    cluster.start_node(2)                 # scripts/cluster start-node DIR 2: the killed node rejoins as a standby
    cluster.down()                        # scripts/cluster down DIR

MapWriters writes maps through anchordb in a loop on several threads and records every answer; a map answered 201
is acknowledged, one answered 503 with Retry-After may or may not exist, anything else is a bad answer.
"""

import json
import os
import shutil
import signal
import subprocess
import tempfile
import threading
import time
import urllib.error
import urllib.parse
import urllib.request

import anchordb_client

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
SCRIPT = os.path.join(ROOT, "scripts", "cluster")
PG_BIN = "/usr/lib/postgresql/15/bin"


def http_json(url, timeout=2.0):
    """(status, parsed JSON or None) of GET url; (None, None) when it cannot connect."""
    try:
        with urllib.request.urlopen(url, timeout=timeout) as r:
            return r.status, json.loads(r.read() or b"null")
    except urllib.error.HTTPError as e:
        try:
            return e.code, json.loads(e.read() or b"null")
        except ValueError:
            return e.code, None
    except (OSError, urllib.error.URLError, ValueError):
        return None, None


def pid_alive(pid):
    """Whether pid is a live process (a zombie counts as gone)."""
    try:
        with open("/proc/%d/stat" % pid, encoding="utf-8", errors="replace") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except (OSError, IndexError):
        return False


def children_of(pid):
    """The PIDs whose parent is pid."""
    out = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open("/proc/%s/stat" % entry, encoding="utf-8", errors="replace") as f:
                    if int(f.read().rsplit(")", 1)[1].split()[1]) == pid:
                        out.append(int(entry))
            except (OSError, IndexError, ValueError):
                pass
    return out


def poll(condition, timeout, what, interval=0.1):
    """Answers condition()'s first true value; raises AssertionError after timeout s."""
    deadline = time.monotonic() + timeout
    while True:
        value = condition()
        if value:
            return value
        if time.monotonic() > deadline:
            raise AssertionError("waited %.0f s for %s" % (timeout, what))
        time.sleep(interval)


class Cluster:
    def __init__(self, servers=1, binary=None, parent=None):
        self.parent = tempfile.mkdtemp(prefix="anchordb-cluster-", dir=parent)
        os.chmod(self.parent, 0o755)  # the postgres user reaches DIR when the tests run as root
        self.dir = os.path.join(self.parent, "c")
        self.binary = binary or os.environ.get("ANCHORDB_BIN")
        if not self.binary:
            raise RuntimeError("ANCHORDB_BIN is not set: point it at the anchordb server binary")
        self.up_seconds = None
        t0 = time.monotonic()
        out = subprocess.run([SCRIPT, "up", self.dir, "--servers", str(servers), "--bin", self.binary],
                             capture_output=True, text=True, timeout=300)
        if out.returncode != 0:
            shutil.rmtree(self.parent, True)
            raise RuntimeError("scripts/cluster up failed (exit %d):\n%s" % (out.returncode, out.stderr[-4000:]))
        self.up_seconds = time.monotonic() - t0
        self.info = self.read_info()
        self.recorded = self.all_recorded_pids()

    def read_info(self):
        with open(os.path.join(self.dir, "cluster.json"), encoding="utf-8") as f:
            return json.load(f)

    def all_recorded_pids(self):
        info = self.read_info() if os.path.exists(os.path.join(self.dir, "cluster.json")) else self.info
        return {pid for pids in info["pids"].values() for pid in pids}

    def down(self):
        """scripts/cluster down DIR; answers its CompletedProcess. The parent temporary folder goes too."""
        if not os.path.exists(self.dir):
            shutil.rmtree(self.parent, True)
            return None
        self.recorded |= self.all_recorded_pids()
        out = subprocess.run([SCRIPT, "down", self.dir], capture_output=True, text=True, timeout=300)
        if not os.path.exists(self.dir):
            shutil.rmtree(self.parent, True)
        return out

    # ---------------------------------------------------------------- Patroni

    def node_index(self, name):
        return int(name[len("node"):])

    def members(self):
        for url in self.info["patroni"]:
            status, body = http_json(url + "/cluster")
            if status == 200 and body:
                return body.get("members", [])
        return []

    def leader(self):
        leaders = [m for m in self.members() if m.get("role") == "leader" and m.get("state") == "running"]
        return leaders[0] if len(leaders) == 1 else None

    def healthy(self, nodes=3):
        """A running leader, a synchronous standby and nodes running members in all."""
        running = [m for m in self.members() if m.get("state") == "running"]
        roles = [m.get("role") for m in running]
        return len(running) == nodes and roles.count("leader") == 1 and "sync_standby" in roles

    def postmaster_pid(self, index):
        try:
            with open(os.path.join(self.dir, "node%d" % index, "data", "postmaster.pid"), encoding="utf-8") as f:
                return int(f.readline())
        except (OSError, ValueError):
            return None

    def kill_leader(self):
        """kill -9 of the leader's postmaster and its Patroni; answers (node index, monotonic time of the kill,
        monotonic time at which the last process of the old primary was gone). A backend outlives its killed
        postmaster for a moment (until it notices) and may still commit, replicated to the synchronous standby: a
        write acknowledged after the second time is one the new primary took."""
        leader = poll(self.leader, 60, "a Patroni leader")
        index = self.node_index(leader["name"])
        info = self.read_info()
        patroni = info["pids"]["patroni"][index - 1]
        postmaster = self.postmaster_pid(index)
        assert patroni and pid_alive(patroni), "the leader's Patroni %s is not running" % patroni
        assert postmaster and pid_alive(postmaster), "the leader's postmaster %s is not running" % postmaster
        children = children_of(postmaster)
        os.kill(patroni, signal.SIGKILL)
        os.kill(postmaster, signal.SIGKILL)
        t = time.monotonic()
        self.recorded |= {patroni, postmaster}
        gone = [patroni, postmaster] + children
        poll(lambda: not any(pid_alive(p) for p in gone), 30, "the killed primary's processes to go", 0.01)
        return index, t, time.monotonic()

    def start_node(self, index):
        out = subprocess.run([SCRIPT, "start-node", self.dir, str(index)], capture_output=True, text=True, timeout=300)
        self.recorded |= self.all_recorded_pids()
        if out.returncode != 0:
            raise AssertionError("scripts/cluster start-node %d failed: %s" % (index, out.stderr[-3000:]))

    # ---------------------------------------------------------------- PostgreSQL directly

    def psql(self, port, sql):
        args = [PG_BIN + "/psql", "-h", "127.0.0.1", "-p", str(port), "-U", "postgres", "-d", "anchordb", "-tAq",
                "-v", "ON_ERROR_STOP=1", "-c", sql]
        if os.getuid() == 0:
            args = ["runuser", "-u", "postgres", "--"] + args
        out = subprocess.run(args, capture_output=True, text=True, timeout=60, cwd="/")
        if out.returncode != 0:
            raise AssertionError("psql on port %s failed: %s" % (port, out.stderr))
        return out.stdout

    def map_ids_on(self, port):
        return set(self.psql(port, "SELECT id FROM maps").split())

    def is_primary(self, port):
        return self.psql(port, "SELECT pg_is_in_recovery()").strip() == "f"


def all_maps(client):
    """Every map id anchordb lists (paged)."""
    ids, cursor = set(), ""
    while True:
        page = client.request("GET", "/v1/maps?limit=1000" + ("&cursor=" + urllib.parse.quote(cursor) if cursor else ""))
        ids |= {m["id"] for m in page["maps"]}
        cursor = page.get("next_cursor")
        if not cursor:
            return ids


class MapWriters:
    """threads writers creating maps through the anchordb servers at urls (round robin), until stop()."""

    def __init__(self, urls, threads=4, prefix="m", timeout=60):
        self.lock = threading.Lock()
        self.acked = set()
        self.unsure = set()     # answered 503 with Retry-After: may or may not exist
        self.bad = []           # (map id, status or exception, body)
        self.answers = []       # (sent monotonic, answered monotonic, status)
        self.statuses = {}
        self._stop = threading.Event()
        self._threads = [threading.Thread(target=self._run, args=(urls[w % len(urls)], "%s%d-" % (prefix, w), timeout),
                                          daemon=True) for w in range(threads)]
        for t in self._threads:
            t.start()

    def _run(self, url, prefix, timeout):
        client = anchordb_client.Client(url, timeout=timeout)
        i = 0
        while not self._stop.is_set():
            map_id = "%s%d" % (prefix, i)
            i += 1  # an id is never reused: a 503 may have committed it
            sent = time.monotonic()
            try:
                r = client.request("POST", "/v1/maps", {"id": map_id}, raw=True)
                status, body, retry_after = r.status, r.body[:300], r.headers.get("retry-after")
            except Exception as e:  # noqa: BLE001 - a dropped connection is a bad answer too
                status, body, retry_after = type(e).__name__, str(e)[:300], None
            done = time.monotonic()
            with self.lock:
                self.answers.append((sent, done, status))
                self.statuses[status] = self.statuses.get(status, 0) + 1
                if status == 201:
                    self.acked.add(map_id)
                elif status == 503 and retry_after:
                    self.unsure.add(map_id)
                else:
                    self.bad.append((map_id, status, body))
            if status != 201:
                time.sleep(0.05)

    def count_acked(self):
        with self.lock:
            return len(self.acked)

    def first_success_after(self, t, sent_after=None):
        """Seconds from t to the answer of the first write sent after sent_after (default t) and acknowledged;
        None if none yet."""
        sent_after = t if sent_after is None else sent_after
        with self.lock:
            done = [d for s, d, status in self.answers if s >= sent_after and status == 201]
        return min(done) - t if done else None

    def statuses_after(self, t):
        with self.lock:
            out = {}
            for s, d, status in self.answers:
                if d >= t:
                    out[status] = out.get(status, 0) + 1
            return out

    def stop(self):
        self._stop.set()
        for t in self._threads:
            t.join(120)
