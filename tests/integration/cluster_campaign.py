#!/usr/bin/env python3
"""The failover campaign of issue 31 (acceptance 1): a site cluster from ./scripts/cluster, writers creating maps
through anchordb the whole time, and N kills of the PostgreSQL primary (kill -9 of its postmaster and its Patroni);
after each kill the first acknowledged write is timed and the killed node rejoins as a standby
(scripts/cluster start-node) before the next kill. At the end: every acknowledged map through anchordb, on the
primary and on each node (the standbys hold the primary's maps); answers other than 201 or 503 with Retry-After.

    ANCHORDB_BIN=build/server/anchordb PYTHONPATH=clients/python \\
        python3 tests/integration/cluster_campaign.py --kills 20 [--servers 1] [--writers 4] [--json out.json]

Exit status 0 when no acknowledged write was lost, no answer was bad (500 or other) and every kill resumed within
--limit seconds (30).
"""

import argparse
import json
import os
import statistics
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import anchordb_client  # noqa: E402
import cluster_support  # noqa: E402
from cluster_support import poll  # noqa: E402


def kill_rounds(cluster, writers, kills, rows):
    """`kills` rounds on a running cluster with `writers` writing: kill -9 of the leader's postmaster and Patroni, the
    seconds to the first acknowledged write after it, the promoted leader, the killed node started again as a standby
    and the cluster healthy before the next round. Prints a line per round and appends it to `rows` (kept when a
    later round fails: AssertionError from poll when a round does not get there); returns `rows`."""
    print("%4s %-6s %-6s %9s %8s %8s %s" % ("kill", "killed", "leader", "resume_s", "rejoin_s", "acked", "answers"),
          flush=True)
    for k in range(1, kills + 1):
        poll(cluster.healthy, 120, "a healthy cluster before kill %d" % k, 0.2)
        before = writers.count_acked()
        poll(lambda: writers.count_acked() >= before + 20, 60, "20 writes before kill %d" % k)
        killed, t_kill, t_gone = cluster.kill_leader()
        resume = poll(lambda: writers.first_success_after(t_kill, t_gone), 120, "a write after kill %d" % k, 0.05)
        # The leader the DCS names once writes flow again: the promoted standby (a killed leader's key lives
        # on for the TTL, so the killed node is started again only now).
        leader = poll(lambda: (lambda m: m if m and m["name"] != "node%d" % killed else None)(cluster.leader()),
                      60, "a new leader after kill %d" % k)
        t_rejoin = time.monotonic()
        cluster.start_node(killed)
        poll(cluster.healthy, 120, "a healthy cluster after the rejoin of node%d" % killed, 0.2)
        rejoin = time.monotonic() - t_rejoin
        answers = writers.statuses_after(t_kill)
        rows.append({"kill": k, "killed": "node%d" % killed, "new_leader": leader["name"],
                     "resume_s": round(resume, 2), "rejoin_s": round(rejoin, 2),
                     "answers_since_kill": {str(s): n for s, n in answers.items()}})
        print("%4d %-6s %-6s %9.2f %8.2f %8d %s" % (k, "node%d" % killed, leader["name"], resume, rejoin,
                                                   writers.count_acked(), answers), flush=True)
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--kills", type=int, default=20)
    parser.add_argument("--servers", type=int, default=1)
    parser.add_argument("--writers", type=int, default=4)
    parser.add_argument("--limit", type=float, default=30.0, help="seconds a kill may take to the first write")
    parser.add_argument("--json", help="write the figures here")
    args = parser.parse_args()

    cluster = cluster_support.Cluster(servers=args.servers)
    print("cluster up in %.1f s (%s), %d anchordb server(s)" % (cluster.up_seconds, cluster.dir, args.servers),
          flush=True)
    rows, failure = [], None
    writers = None
    try:
        writers = cluster_support.MapWriters(cluster.info["anchordb"], threads=args.writers, prefix="k")
        kill_rounds(cluster, writers, args.kills, rows)
    except Exception as e:  # any failure is the campaign's result; the cluster is brought down below either way
        failure = "%s: %s" % (type(e).__name__, e)
        print("campaign stopped: " + failure, flush=True)
    finally:
        if writers is not None:
            writers.stop()

    result = {"kills": len(rows), "rows": rows, "failure": failure}
    try:
        if writers is not None:
            client = anchordb_client.Client(cluster.info["anchordb"][0], timeout=60)
            through_anchordb = cluster_support.all_maps(client)
            leader = poll(cluster.leader, 60, "a leader at the end")
            on_primary = cluster.map_ids_on(leader["port"])
            node_equal = {}
            for i, port in enumerate(cluster.info["postgres"], 1):
                try:
                    poll(lambda: cluster.map_ids_on(port) == on_primary, 60, "node%d to equal the primary" % i, 0.5)
                    node_equal["node%d" % i] = True
                except AssertionError:
                    node_equal["node%d" % i] = False
            resumes = [r["resume_s"] for r in rows]
            result.update({
                "acknowledged": len(writers.acked),
                "answered_503": len(writers.unsure),
                "statuses": {str(s): n for s, n in writers.statuses.items()},
                "lost_through_anchordb": sorted(writers.acked - through_anchordb),
                "lost_on_primary": sorted(writers.acked - on_primary),
                "nodes_equal_primary": node_equal,
                "answers_500": writers.statuses.get(500, 0),
                "bad_answers": writers.bad[:20],
                "bad_count": len(writers.bad),
                "resume_median_s": round(statistics.median(resumes), 2) if resumes else None,
                "resume_worst_s": max(resumes) if resumes else None,
                "resume_best_s": min(resumes) if resumes else None,
            })
    finally:
        out = cluster.down()
        result["down_ok"] = out is not None and out.returncode == 0
        result["dir_left"] = os.path.exists(cluster.dir)

    summary = {k: v for k, v in result.items() if k != "rows"}
    print(json.dumps(summary, indent=1))
    if args.json:
        with open(args.json, "w", encoding="utf-8") as f:
            json.dump(result, f, indent=1)
    ok = (failure is None and result.get("lost_through_anchordb") == [] and result.get("lost_on_primary") == []
          and result.get("bad_count") == 0 and all(result.get("nodes_equal_primary", {}).values())
          and result.get("resume_worst_s") is not None and result["resume_worst_s"] < args.limit
          and result["down_ok"] and not result["dir_left"])
    print("campaign " + ("passed" if ok else "FAILED"))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
