"""A site cluster from ./scripts/cluster (issue 31): one etcd, three PostgreSQL 15 nodes under Patroni (synchronous
mode strict) and one anchordb server on the multi-host connection string.

The tests run in order on one cluster (bringing one up costs about 20 s): its shape and writes through anchordb;
the primary killed (kill -9 of its postmaster and its Patroni) while four clients write maps: every answer is 201
or 503 with Retry-After, never 500, writes resume after the promotion (the seconds from the kill to the first
acknowledged write are printed and must stay under 30), every acknowledged map is there through anchordb and on
the new primary, and the old primary rejoins as a standby holding them too; then `down` leaves no process and no
folder."""

import os
import time
import unittest

import anchordb_client
import cluster_support
from cluster_support import poll

RESUME_LIMIT_S = 30.0  # issue 31, acceptance 1


def shape_errors(info):
    """What is wrong with cluster.json's shape (issue 31), as a list of messages."""
    errors = []
    if set(info) != {"anchordb", "patroni", "postgres", "pids"}:
        errors.append("keys %s" % sorted(info))
    for key in ("anchordb", "patroni"):
        urls = info.get(key, [])
        if not urls or not all(isinstance(u, str) and u.startswith("http://127.0.0.1:") for u in urls):
            errors.append("%s: %r" % (key, urls))
    ports = info.get("postgres", [])
    if len(ports) != 3 or not all(isinstance(p, int) and 0 < p < 65536 for p in ports):
        errors.append("postgres: %r" % ports)
    pids = info.get("pids", {})
    if set(pids) != {"anchordb", "postgres", "patroni", "etcd"}:
        errors.append("pids keys %s" % sorted(pids))
    else:
        expected = {"anchordb": len(info.get("anchordb", [])), "postgres": 3, "patroni": 3, "etcd": 1}
        for key, n in expected.items():
            if len(pids[key]) != n or not all(isinstance(p, int) and p > 0 for p in pids[key]):
                errors.append("pids.%s: %r (expected %d)" % (key, pids[key], n))
    return errors


class ClusterTest(unittest.TestCase):
    cluster = None

    @classmethod
    def setUpClass(cls):
        cls.cluster = cluster_support.Cluster(servers=1)
        print("cluster up in %.1f s: %s" % (cls.cluster.up_seconds, cls.cluster.dir))

    @classmethod
    def tearDownClass(cls):
        if cls.cluster is not None:
            cls.cluster.down()  # when test_3 did not run or failed early

    def client(self, timeout=60):
        return anchordb_client.Client(self.cluster.info["anchordb"][0], timeout=timeout)

    def test_1_up_shape_leader_sync_standby_and_writes(self):
        c = self.cluster
        self.assertEqual(shape_errors(c.info), [], c.info)
        self.assertEqual(len(c.info["anchordb"]), 1)
        for pid in c.all_recorded_pids():
            self.assertTrue(cluster_support.pid_alive(pid), "recorded pid %d is not running" % pid)
        for url in c.info["patroni"]:
            self.assertEqual(cluster_support.http_json(url + "/health")[0], 200, url)
        members = c.members()
        roles = sorted(m["role"] for m in members)
        self.assertEqual(roles, ["leader", "replica", "sync_standby"], members)
        leader = c.leader()
        self.assertIsNotNone(leader)
        leader_url = c.info["patroni"][c.node_index(leader["name"]) - 1]
        self.assertEqual(cluster_support.http_json(leader_url + "/leader")[0], 200)
        status, config = cluster_support.http_json(leader_url + "/config")
        self.assertEqual(status, 200)
        self.assertTrue(config.get("synchronous_mode") and config.get("synchronous_mode_strict"), config)
        self.assertEqual(config.get("synchronous_node_count", 1), 1, config)
        self.assertTrue(config["postgresql"]["use_pg_rewind"], config)
        self.assertTrue(c.is_primary(leader["port"]))
        # Synchronous replication is on: the primary names one synchronous standby, which streams.
        self.assertEqual(c.psql(leader["port"], "SELECT count(*) FROM pg_stat_replication WHERE sync_state = 'sync'")
                         .strip(), "1")

        client = self.client()
        self.assertEqual(client.health().get("status"), "ok")
        for i in range(10):
            r = client.request("POST", "/v1/maps", {"id": "up-%d" % i}, raw=True)
            self.assertEqual(r.status, 201, r.body)
        ids = {"up-%d" % i for i in range(10)}
        self.assertLessEqual(ids, cluster_support.all_maps(client))
        self.assertLessEqual(ids, c.map_ids_on(leader["port"]))
        sync = [m for m in c.members() if m["role"] == "sync_standby"][0]
        # What the primary acknowledged is on the synchronous standby once it has replayed it (read on the standby).
        poll(lambda: ids <= c.map_ids_on(sync["port"]), 30, "the maps on the synchronous standby")

    def test_2_primary_killed_under_writes_loses_no_acknowledged_write(self):
        c = self.cluster
        poll(lambda: c.healthy(), 60, "a healthy cluster (leader and synchronous standby)")
        old_leader = c.leader()
        writers = cluster_support.MapWriters(c.info["anchordb"], threads=4, prefix="f")
        try:
            poll(lambda: writers.count_acked() >= 40, 60, "40 acknowledged writes before the kill")
            killed, t_kill, t_gone = c.kill_leader()
            self.assertEqual("node%d" % killed, old_leader["name"])
            resume = poll(lambda: writers.first_success_after(t_kill, t_gone), 90,
                          "an acknowledged write after the kill")
            acked_at_resume = writers.count_acked()
            poll(lambda: writers.count_acked() >= acked_at_resume + 40, 60, "40 more writes after the promotion")
        finally:
            writers.stop()
        new_leader = poll(c.leader, 60, "a leader after the kill")
        print("failover: killed %s (its processes gone %.2f s later), new leader %s, first acknowledged write "
              "%.2f s after the kill; answers %s; acknowledged %d, answered 503 %d" % (
                  old_leader["name"], t_gone - t_kill, new_leader["name"], resume, writers.statuses,
                  len(writers.acked), len(writers.unsure)))
        self.assertEqual(writers.bad, [], "answers other than 201, or 503 with Retry-After")
        self.assertNotEqual(new_leader["name"], old_leader["name"])
        self.assertLess(resume, RESUME_LIMIT_S)

        client = self.client()
        self.assertEqual(writers.acked - cluster_support.all_maps(client), set(),
                         "acknowledged maps missing through anchordb")
        self.assertTrue(c.is_primary(new_leader["port"]))
        self.assertEqual(writers.acked - c.map_ids_on(new_leader["port"]), set(),
                         "acknowledged maps missing on the new primary")

        # The old primary rejoins as a standby (pg_rewind where its timeline diverged) and holds every map.
        c.start_node(killed)
        poll(lambda: c.healthy(), 90, "three running members with a synchronous standby after the rejoin")
        port = c.info["postgres"][killed - 1]
        self.assertFalse(c.is_primary(port))
        primary_ids = c.map_ids_on(new_leader["port"])
        poll(lambda: c.map_ids_on(port) == primary_ids, 60, "the rejoined node to hold the primary's maps")
        r = client.request("POST", "/v1/maps", {"id": "after-rejoin"}, raw=True)
        self.assertEqual(r.status, 201, r.body)

    def test_3_down_leaves_no_process_and_no_folder(self):
        c = self.cluster
        pids = c.all_recorded_pids() | c.recorded
        for index in (1, 2, 3):
            pid = c.postmaster_pid(index)
            if pid:
                pids.add(pid)
        directory = c.dir
        t0 = time.monotonic()
        out = c.down()
        print("down in %.1f s" % (time.monotonic() - t0))
        self.assertEqual(out.returncode, 0, out.stderr)
        self.assertFalse(os.path.exists(directory), "down left %s" % directory)
        self.assertEqual(sorted(p for p in pids if cluster_support.pid_alive(p)), [], "processes left running")
        ClusterTest.cluster = None


if __name__ == "__main__":
    unittest.main()
