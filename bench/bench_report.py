#!/usr/bin/env python3
"""Summaries for scripts/bench (standard library only).

  bench_report.py grid GRID_JSON
      prints the median time of every grid benchmark from Google Benchmark's JSON and checks the SPEC section 7
      goal of the observation update (<= 2 ms on 400x400 cells).
  bench_report.py http OUT_JSON MANIFEST
      MANIFEST has one tab-separated line per wrk run: key, description, url, wrk output file, ss snapshot file,
      response body bytes, connections opened. Prints the side-by-side table with the ratios anchordb / peer and
      writes OUT_JSON.
  bench_report.py engines OUT_JSON MANIFEST INGEST_SQLITE INGEST_POSTGRESQL
      MANIFEST: key (<engine>_<route>_<round>), description, url, wrk output file per line; INGEST_*: the JSON
      lines of anchordb_ingest_bench on each engine. Prints SQLite beside PostgreSQL (each engine's median round by
      req/s; p50 of that round, p99 and max the worst of all rounds), the ratio of the medians with the worst and best
      ratio of one round's pair, and the goals (reads on PostgreSQL >= 0.5x SQLite's req/s, on the medians; durable
      ingest >= 60 frames/s on both), and writes OUT_JSON.
"""
import json
import re
import sys

OBSERVATION_GOAL_MS = 2.0
READ_GOAL_RPS = 5000.0
READ_GOAL_P99_MS = 5.0


def to_ms(value, unit):
    return value * {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[unit]


def grid(path):
    with open(path) as f:
        doc = json.load(f)
    runs = {}
    for b in doc.get("benchmarks", []):
        name = b.get("run_name", b["name"])
        entry = runs.setdefault(name, {"iterations": [], "median": None, "error": None, "counters": {}})
        if b.get("error_occurred"):
            entry["error"] = b.get("error_message", "error")
            continue
        if b.get("run_type") == "aggregate":
            if b.get("aggregate_name") == "median":
                entry["median"] = to_ms(b["real_time"], b.get("time_unit", "ns"))
            continue
        entry["iterations"].append(to_ms(b["real_time"], b.get("time_unit", "ns")))
        for k, v in b.items():
            if isinstance(v, (int, float)) and k not in (
                    "family_index", "per_family_instance_index", "repetitions", "repetition_index", "threads",
                    "iterations", "real_time", "cpu_time", "bytes_per_second", "items_per_second"):
                entry["counters"][k] = v
    ctx = doc.get("context", {})
    print(f"grid benchmarks ({ctx.get('num_cpus', '?')} CPUs at {ctx.get('mhz_per_cpu', '?')} MHz, "
          f"Google Benchmark library built {ctx.get('library_build_type', '?')}), median wall time per operation:")
    goal_lines = []
    for name, e in runs.items():
        if e["error"]:
            print(f"  {name:<40} SKIPPED: {e['error']}")
            continue
        t = e["median"] if e["median"] is not None else (sorted(e["iterations"])[len(e["iterations"]) // 2]
                                                         if e["iterations"] else float("nan"))
        extra = ", ".join(f"{k}={v:g}" for k, v in e["counters"].items())
        print(f"  {name:<40} {t:9.3f} ms   {extra}")
        if name.startswith("BM_ObservationUpdate"):
            verdict = "meets" if t <= OBSERVATION_GOAL_MS else "MISSES"
            goal_lines.append(f"  {name}: {t:.3f} ms {verdict} the <= {OBSERVATION_GOAL_MS:g} ms goal "
                              f"({t / OBSERVATION_GOAL_MS * 100:.0f} % of it)")
    if goal_lines:
        print("SPEC 7 goal, grid observation update on 400x400 cells <= 2 ms:")
        print("\n".join(goal_lines))


def parse_wrk(path):
    text = open(path).read()
    m = re.search(r"^WRK_JSON (\{.*\})$", text, re.M)
    if not m:
        raise SystemExit(f"bench_report: no WRK_JSON line in {path} (did wrk run with bench/wrk_report.lua?)")
    return json.loads(m.group(1))


def parse_ss(path):
    """Server-side sockets of the port: how many there were and how many had sent no byte (never served)."""
    try:
        text = open(path).read()
    except OSError:
        return None
    # `ss -tniH`: one line per socket (Recv-Q Send-Q local peer), then its indented TCP info line(s).
    infos = []
    for line in text.splitlines():
        if not line.strip():
            continue
        if line[:1].isspace() and infos:
            infos[-1] += " " + line
        else:
            infos.append(line)
    sockets = len(infos)
    served = 0
    for info in infos:
        m = re.search(r"bytes_sent:(\d+)", info)
        if m and int(m.group(1)) > 0:
            served += 1
    return {"sockets": sockets, "served": served, "starved": sockets - served}


def http(out_path, manifest_path):
    runs = []
    for line in open(manifest_path):
        line = line.rstrip("\n")
        if not line:
            continue
        key, description, url, wrk_path, ss_path, body_bytes, connections = line.split("\t")
        w = parse_wrk(wrk_path)
        seconds = w["duration_us"] / 1e6
        lat = {k: v / 1000.0 for k, v in w["latency_us"].items()}  # ms
        errors = sum(w["errors"].values())
        runs.append({
            "key": key, "description": description, "url": url, "body_bytes": int(body_bytes),
            "connections": int(connections), "requests": w["requests"], "duration_s": seconds,
            "requests_per_s": w["requests"] / seconds if seconds > 0 else 0.0,
            "latency_ms": lat, "errors": w["errors"], "error_count": errors,
            "server_sockets": parse_ss(ss_path),
        })
    by_key = {r["key"]: r for r in runs}
    W = max(len("ratio anchordb / " + r["description"]) for r in runs) + 2

    print(f"{'':<{W}}{'req/s':>10}{'p50 ms':>9}{'p90 ms':>9}{'p99 ms':>9}{'max ms':>9}{'errors':>8}{'served conns':>14}")
    for r in runs:
        s = r["server_sockets"]
        conns = f"{s['served']}/{r['connections']}" if s else "?"
        lat = r["latency_ms"]
        print(f"{r['description']:<{W}}{r['requests_per_s']:>10.0f}{lat['p50']:>9.3f}{lat['p90']:>9.3f}"
              f"{lat['p99']:>9.3f}{lat['max']:>9.3f}{r['error_count']:>8}{conns:>14}")
    ratios = {}
    a = by_key.get("anchordb")
    for peer_key in ("peer", "peer_nodelay"):
        p = by_key.get(peer_key)
        if not a or not p:
            continue
        ratio = {
            "requests_per_s": a["requests_per_s"] / p["requests_per_s"] if p["requests_per_s"] else None,
            "p50": a["latency_ms"]["p50"] / p["latency_ms"]["p50"] if p["latency_ms"]["p50"] else None,
            "p99": a["latency_ms"]["p99"] / p["latency_ms"]["p99"] if p["latency_ms"]["p99"] else None,
        }
        ratios[f"anchordb/{peer_key}"] = ratio
        fmt = lambda v: f"{v:.3f}" if v is not None else "n/a"
        print(f"{'ratio anchordb / ' + p['description']:<{W}}{fmt(ratio['requests_per_s']):>10}"
              f"{fmt(ratio['p50']):>9}{'':>9}{fmt(ratio['p99']):>9}")

    warnings = []
    for r in runs:
        s = r["server_sockets"]
        if s and s["starved"] > 0:
            warnings.append(
                f"{r['description']}: {s['starved']} of {s['sockets']} connections had received no response "
                f"{'' if s['sockets'] == r['connections'] else '(sockets seen ' + str(s['sockets']) + ') '}"
                f"when sampled late in the run; req/s and latency above come from the {s['served']} served "
                f"connections only (wrk leaves unanswered requests out of its histogram)")
        if r["error_count"]:
            warnings.append(f"{r['description']}: wrk counted errors {r['errors']}")
    for a in (r for r in runs if r["key"].startswith("anchordb")):
        ok = a["requests_per_s"] >= READ_GOAL_RPS and a["latency_ms"]["p99"] <= READ_GOAL_P99_MS and not (
            a["server_sockets"] and a["server_sockets"]["starved"])
        print(f"SPEC 7 goal, read queries >= {READ_GOAL_RPS:.0f} req/s with p99 <= {READ_GOAL_P99_MS:g} ms: "
              f"{a['description']}: {a['requests_per_s']:.0f} req/s, p99 {a['latency_ms']['p99']:.3f} ms -> "
              f"{'met' if ok else 'NOT met'}")
    for w in warnings:
        print("WARNING: " + w)

    with open(out_path, "w") as f:
        json.dump({"runs": runs, "ratios": ratios, "warnings": warnings,
                   "goal": {"requests_per_s": READ_GOAL_RPS, "p99_ms": READ_GOAL_P99_MS}}, f, indent=2)
        f.write("\n")


ENGINE_READ_RATIO_GOAL = 0.5
INGEST_GOAL_FPS = 60.0


def _median_round(rounds):
    """The round whose req/s is the median (the lower middle for an even count), with the worst p99 and max."""
    ordered = sorted(rounds, key=lambda r: r["requests_per_s"])
    mid = dict(ordered[(len(ordered) - 1) // 2])
    mid["latency_ms"] = dict(mid["latency_ms"], p99=max(r["latency_ms"]["p99"] for r in rounds),
                             max=max(r["latency_ms"]["max"] for r in rounds))
    mid["errors"] = sum(r["errors"] for r in rounds)
    return mid


def engines(out_path, manifest_path, ingest_sqlite, ingest_postgresql):
    runs = {}
    for line in open(manifest_path):
        if not line.strip():
            continue
        key, description, url, wrk_path = line.rstrip("\n").split("\t")
        w = parse_wrk(wrk_path)
        seconds = w["duration_us"] / 1e6
        runs[key] = {"description": description, "url": url, "requests": w["requests"],
                     "requests_per_s": w["requests"] / seconds if seconds > 0 else 0.0,
                     "latency_ms": {k: v / 1000.0 for k, v in w["latency_us"].items()},
                     "errors": sum(w["errors"].values()), "error_kinds": w["errors"]}
    ingest = {"sqlite": [json.loads(l) for l in open(ingest_sqlite) if l.strip()],
              "postgresql": [json.loads(l) for l in open(ingest_postgresql) if l.strip()]}
    print(f"{'':<28}{'SQLite req/s':>13}{'p50':>8}{'p99':>8}{'max ms':>9}{'PostgreSQL req/s':>18}{'p50':>8}{'p99':>8}"
          f"{'max ms':>9}{'PG/SQLite':>11}{'worst':>7}{'best':>6}{'errors':>8}")
    ratios, verdicts = {}, []
    for route, what, kind in (("layer", "GET layer metadata", "read"), ("where", "GET where?label=keys", "read"),
                              ("label", "POST a label", "write")):
        pairs = []
        k = 1
        while f"sqlite_{route}_{k}" in runs and f"postgresql_{route}_{k}" in runs:
            pairs.append((runs[f"sqlite_{route}_{k}"], runs[f"postgresql_{route}_{k}"]))
            k += 1
        if not pairs:
            raise SystemExit(f"bench_report: no rounds of {route} in {manifest_path}")
        a, b = _median_round([p[0] for p in pairs]), _median_round([p[1] for p in pairs])
        ratio = b["requests_per_s"] / a["requests_per_s"] if a["requests_per_s"] else 0.0
        paired = [q["requests_per_s"] / p["requests_per_s"] if p["requests_per_s"] else 0.0 for p, q in pairs]
        ratios[route] = {"median_over_median": ratio, "rounds": len(pairs), "round_ratios": paired,
                         "sqlite_rounds_per_s": [p[0]["requests_per_s"] for p in pairs],
                         "postgresql_rounds_per_s": [p[1]["requests_per_s"] for p in pairs]}
        la, lb = a["latency_ms"], b["latency_ms"]
        print(f"{what + ' (' + kind + ')':<28}{a['requests_per_s']:>13.0f}{la['p50']:>8.2f}{la['p99']:>8.2f}{la['max']:>9.1f}"
              f"{b['requests_per_s']:>18.0f}{lb['p50']:>8.2f}{lb['p99']:>8.2f}{lb['max']:>9.1f}{ratio:>11.3f}"
              f"{min(paired):>7.3f}{max(paired):>6.3f}{a['errors'] + b['errors']:>8}")
        for p in pairs:
            for r in p:
                if r["errors"]:
                    print(f"    {r['description']}: wrk counted errors {r['error_kinds']} (status: answers other than 2xx/3xx)")
        if kind == "read":
            verdicts.append(f"reads on PostgreSQL >= {ENGINE_READ_RATIO_GOAL}x SQLite, {what}: {ratio:.3f} over "
                            f"{len(pairs)} rounds (one round's pair: worst {min(paired):.3f}, best {max(paired):.3f}) -> "
                            f"{'met' if ratio >= ENGINE_READ_RATIO_GOAL and not a['errors'] + b['errors'] else 'NOT met'}")
    for engine, lines in ingest.items():
        for r in lines:
            ok = r["frames_per_s"] >= INGEST_GOAL_FPS
            print(f"durable ingest on {engine}, {r['encoding']}: {r['frames_per_s']:.1f} frames/s (mean "
                  f"{r['ms_per_frame']:.2f} ms, p99 {r.get('p99_ms', float('nan')):.2f} ms, worst "
                  f"{r.get('max_ms', float('nan')):.2f} ms per frame)")
            verdicts.append(f"durable ingest >= {INGEST_GOAL_FPS:g} frames/s on {engine}, {r['encoding']}: "
                            f"{r['frames_per_s']:.1f} -> {'met' if ok else 'NOT met'}")
    for v in verdicts:
        print("goal: " + v)
    with open(out_path, "w") as f:
        json.dump({"runs": runs, "ratios_postgresql_over_sqlite": ratios, "ingest": ingest, "verdicts": verdicts}, f,
                  indent=2)
        f.write("\n")


def main(argv):
    if len(argv) == 3 and argv[1] == "grid":
        grid(argv[2])
    elif len(argv) == 4 and argv[1] == "http":
        http(argv[2], argv[3])
    elif len(argv) == 6 and argv[1] == "engines":
        engines(*argv[2:6])
    else:
        print(__doc__, file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
