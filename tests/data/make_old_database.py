#!/usr/bin/env python3
"""Writes a small but complete memory with the anchordb server of an earlier release, for tests/data/.

    python3 tests/data/make_old_database.py --server /tmp/anchordb-old/bin/anchordb-dfbf084 \
        --commit dfbf084 --out tests/data/schema_0004_dfbf084.sqlite

Starts `SERVER serve --db OUT --port 0` on loopback (through tests/integration/harness.py), asks it which routes it
has (GET /v1/openapi.json) and writes every entity those routes can make: maps, occupancy imports (PGM and PNG), a
probability layer with observations, a fused and a label layer, agents, API tokens (`token create`); scene models
with synthetic depth frames (a floor, a wall and a box that appears and later goes), manual keyframes, closed,
merged/superseded and still observing models; furniture graphs with descriptions and a reset; instances, events,
labels, pins, relevance, re-analysis and a forgetting job (dry run); and, from schema 0007 on, what the later
schemas added (old_database_later.py: audit log, analysis queue, pose covariance, OctoMap, anchored features, a
codebook and classifiers, a shape model, furniture instances, an instance classification). Then it reads everything
back through the API and writes OUT minus ".sqlite" plus ".json": the manifest that
tests/integration/test_old_databases.py compares the current server's answers with. The server is stopped with
SIGTERM, so the file is checkpointed (no -wal is left).

Standard library only; no randomness and no clock (time stamps are fixed), so a rerun with the same binary writes
the same memory (row time stamps the server takes from its own clock differ).
"""

import argparse
import copy
import hashlib
import json
import math
import os
import sqlite3
import struct
import sys
import time
import urllib.parse

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path[:0] = [os.path.join(ROOT, "clients", "python"), os.path.join(ROOT, "tests", "integration")]

import harness  # noqa: E402  (tests/integration: starts a server binary, synthetic maps, PNG helpers)
import old_database_later  # noqa: E402  (the parts of schemas 0007-0016, beside this file)

T0_NS = 1795400000000000000  # 2026-11-22T... : every stamp the script sends is T0_NS + an offset
FRAME_NS = 33000000
CAMERA = {"width": 160, "height": 120, "fx": 140.0, "fy": 140.0, "cx": 79.5, "cy": 59.5}
WALL_X_M = 3.0
BOX = ((1.5, -0.2, 0.0), (1.9, 0.2, 0.3))  # the box that appears on the floor at place A: min, max corner [m]


# ---------------------------------------------------------------- geometry and images

def camera_pose(x, y, z, yaw, tilt):
    """Pose of the camera optical frame (z forward, x right, y down) in the map: at (x, y, z), looking along `yaw`,
    `tilt` [rad] below the horizon. Returns (pose JSON, rotation matrix columns x, y, z of the optical frame)."""
    cy_, sy = math.cos(yaw), math.sin(yaw)
    ct, st = math.cos(tilt), math.sin(tilt)
    z_axis = (ct * cy_, ct * sy, -st)
    y_axis = (-st * cy_, -st * sy, -ct)
    x_axis = (y_axis[1] * z_axis[2] - y_axis[2] * z_axis[1], y_axis[2] * z_axis[0] - y_axis[0] * z_axis[2],
              y_axis[0] * z_axis[1] - y_axis[1] * z_axis[0])
    m = [[x_axis[r], y_axis[r], z_axis[r]] for r in range(3)]  # m[row][col]
    trace = m[0][0] + m[1][1] + m[2][2]
    if trace > 0:
        s = 2.0 * math.sqrt(trace + 1.0)
        q = ((m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s, 0.25 * s)
    else:
        i = max(range(3), key=lambda k: m[k][k])
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * math.sqrt(1.0 + m[i][i] - m[j][j] - m[k][k])
        v = [0.0, 0.0, 0.0]
        v[i] = 0.25 * s
        v[j] = (m[j][i] + m[i][j]) / s
        v[k] = (m[k][i] + m[i][k]) / s
        q = (v[0], v[1], v[2], (m[k][j] - m[j][k]) / s)
    pose = {"position": [x, y, z], "orientation": [round(c, 9) for c in q]}
    return pose, (x_axis, y_axis, z_axis), (x, y, z)


def render_depth(view, boxes):
    """uint16 depth [mm] (little-endian bytes, row-major) of the floor z = 0, the wall x = WALL_X_M and `boxes`
    ((min, max) corners) seen from `view` (camera_pose's result) with CAMERA; 0 where nothing is within 4 m."""
    _, (ax, ay, az), c = view
    out = bytearray()
    for v in range(CAMERA["height"]):
        for u in range(CAMERA["width"]):
            a, b = (u - CAMERA["cx"]) / CAMERA["fx"], (v - CAMERA["cy"]) / CAMERA["fy"]
            d = [a * ax[i] + b * ay[i] + az[i] for i in range(3)]  # ray with optical z = 1: t is the depth
            best = math.inf
            if d[2] < -1e-9:
                best = min(best, -c[2] / d[2])
            if d[0] > 1e-9:
                best = min(best, (WALL_X_M - c[0]) / d[0])
            for lo, hi in boxes:
                t0, t1 = 0.0, math.inf
                for i in range(3):
                    if abs(d[i]) < 1e-12:
                        if not lo[i] <= c[i] <= hi[i]:
                            t0, t1 = 1.0, 0.0
                        continue
                    ta, tb = (lo[i] - c[i]) / d[i], (hi[i] - c[i]) / d[i]
                    t0, t1 = max(t0, min(ta, tb)), min(t1, max(ta, tb))
                if t0 <= t1:
                    best = min(best, t0)
            out += struct.pack("<H", int(round(best * 1000.0)) if best < 4.0 else 0)
    return bytes(out)


def rect(x0, y0, x1, y1):
    return [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]


def yaw_pose(x, y, yaw):
    return {"position": [x, y, 0.0], "orientation": [0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0)]}


def sha256(data):
    return hashlib.sha256(data).hexdigest()


# ---------------------------------------------------------------- reading back (shared with the test)

def read_entry(client, entry):
    """Reads one manifest entry from a server: {"path", "as": json | bytes | png, "fields"?}. Returns what the
    manifest keeps of it: the JSON (only `fields` when given), or {"sha256", "bytes", headers} of the body (for png:
    of the decoded pixels, so a different PNG encoder with the same pixels reads back the same)."""
    r = client.request("GET", entry["path"], raw=True)
    if r.status != 200:
        try:
            code = r.json()["error"]["code"]
        except (ValueError, KeyError, TypeError):
            code = None
        return {"status": r.status, "error_code": code}
    if entry["as"] == "json":
        value = r.json()
        if "fields" in entry:
            value = {k: value.get(k) for k in entry["fields"]}
        return value
    body = r.body
    out = {}
    if entry["as"] == "png":
        w, h, depth, body = harness.decode_png_grey_any(body)
        out.update(width=w, height=h, bit_depth=depth)
    for header in ("x-grid-width", "x-grid-height", "x-layer-version", "x-element"):
        if header in r.headers:
            out[header] = r.headers[header]
    out.update(sha256=sha256(body), bytes=len(body))
    return out


# ---------------------------------------------------------------- the memory

class Writer(old_database_later.LaterParts):
    def __init__(self, server):
        self.c = server.client
        self.server = server
        self.openapi = self.c.openapi()
        paths = self.openapi["paths"]
        self.routes = {(m.upper(), p) for p, ops in paths.items() for m in ops}
        self.entries = []      # what is read back: manifest["reads"]
        self.expect = {}       # a semantic summary for targeted checks
        self.steps = []        # what was written, in order (for the README and for debugging)

    def has(self, method, path):
        return (method, path) in self.routes

    def call(self, method, path, body=None, headers=None):
        self.steps.append("%s %s" % (method, path.split("?")[0]))
        return self.c.request(method, path, body, headers)

    def read(self, path, kind="json", fields=None, may_fail=False):
        e = {"path": path, "as": kind}
        if fields:
            e["fields"] = list(fields)
        e["value"] = read_entry(self.c, e)
        if not may_fail and set(e["value"]) == {"status", "error_code"}:
            raise RuntimeError("GET %s failed: %s" % (path, e["value"]))
        self.entries.append(e)
        return copy.deepcopy(e["value"])  # the caller's edits must not reach the manifest

    # ------------------------------------------------------------ grid

    def write_grid(self):
        c = self
        c.call("POST", "/v1/maps", {"id": "home", "name": "Our flat"})
        c.call("POST", "/v1/maps", {"id": "garage", "name": "Garage"})
        flat = harness.SyntheticMap(40, 30, resolution=0.1, origin=(-0.5, -1.5, 0.0),
                                    walls=[(20, 0, 20, 18)], unknown=[(30, 20, 38, 28)])
        self.c.import_occupancy("home", "floor", flat.yaml("floor.pgm"), flat.pgm())
        self.steps.append("PUT /v1/maps/home/layers/floor (map_server import, PGM)")
        garage = harness.SyntheticMap(16, 12, resolution=0.05, origin=(0.0, 0.0, 0.0), walls=[(6, 3, 9, 5)])
        self.c.import_occupancy("garage", "floor", garage.yaml("floor.png"), garage.png())
        self.steps.append("PUT /v1/maps/garage/layers/floor (map_server import, PNG)")
        c.call("PUT", "/v1/maps/home/layers/seen", {"kind": "probability", "base": "floor",
                                                   "log_odds": {"hit": 0.75, "miss": 0.35, "clamp_min": 0.1,
                                                                "clamp_max": 0.95}})
        observations = [((0.0, 0.0, 0.0), [rect(0.5, -0.5, 1.0, 0.0)]),
                        ((0.0, 0.0, 0.3), [rect(0.5, -0.5, 1.0, 0.0), rect(1.0, 0.2, 1.3, 0.6)]),
                        ((1.0, 1.0, -math.pi / 2), [rect(0.8, -0.3, 1.2, 0.1)])]
        for i, ((x, y, yaw), stimulus) in enumerate(observations):
            c.call("POST", "/v1/maps/home/layers/seen/observations",
                   {"pose": yaw_pose(x, y, yaw), "fov_rad": 1.2, "range_m": 2.5, "stimulus": stimulus,
                    "stamp": T0_NS + i * 1000000000})
        c.call("PUT", "/v1/maps/home/layers/unseen_free", {"kind": "fused", "op": "and_not", "operands": [
            {"layer": "floor", "threshold": 0.5}, {"layer": "seen", "threshold": 0.6}]})
        c.call("PUT", "/v1/maps/home/layers/rooms", {"kind": "label", "base": "floor", "labels": {"1": "kitchen"}})
        c.call("POST", "/v1/maps/home/layers/rooms/labels", {"label": "kitchen", "polygons": [rect(-0.4, -1.4, 1.4, 0.0)]})
        c.call("POST", "/v1/maps/home/layers/rooms/labels",
               {"label": "hall", "polygons": [rect(0.5, -0.2, 1.4, 1.4), rect(2.0, 0.0, 2.4, 0.4)]})
        c.call("PUT", "/v1/maps/home/agents/alice", {"position": [0.6, 0.4], "heading_rad": 0.5,
                                                     "velocity": [0.2, -0.1], "stamp": T0_NS + 5000000000})
        c.call("PUT", "/v1/maps/home/agents/bob", {"position": [1.2, -0.8], "heading_rad": -2.0,
                                                   "stamp": T0_NS + 6000000000})
        c.call("PUT", "/v1/maps/home/agents/alice", {"position": [0.7, 0.5], "heading_rad": 0.6,
                                                     "velocity": [0.1, 0.1], "stamp": T0_NS + 7000000000})
        c.call("PUT", "/v1/maps/garage/agents/robot", {"position": [0.3, 0.2], "heading_rad": 1.0})

    def read_grid(self):
        self.read("/v1/maps")
        layers = {}
        for m in ("home", "garage"):
            self.read("/v1/maps/%s" % m)
            for layer in self.read("/v1/maps/%s/layers" % m)["layers"]:
                name = layer["name"]
                path = "/v1/maps/%s/layers/%s" % (m, name)
                info = self.read(path + "?format=json&statistics=true")
                raw = self.read(path + "?format=raw", "bytes")
                cells = self.c.get_layer(m, name, "raw")
                element = {"probability": "f", "label": "H"}.get(info["kind"], "B")
                values = struct.unpack("<%d%s" % (len(cells) // struct.calcsize(element), element), cells)
                layers["%s/%s" % (m, name)] = {"kind": info["kind"], "width": int(raw["x-grid-width"]),
                                               "height": int(raw["x-grid-height"]), "sha256": raw["sha256"],
                                               "distinct_values": len(set(values))}
                if info["kind"] == "occupancy":
                    self.read(path + "?format=yaml", "bytes")
                    self.read(path + "?format=pgm", "bytes")
            for agent in self.read("/v1/maps/%s/agents" % m)["agents"]:
                self.read("/v1/maps/%s/agents/%s" % (m, agent["id"]))
        self.expect["maps"] = {"home": "Our flat", "garage": "Garage"}
        self.expect["layers"] = layers
        self.expect["agents"] = {"home": ["alice", "bob"], "garage": ["robot"]}

    # ------------------------------------------------------------ scenes

    def frames(self, scene, view, boxes_at, n, start_ns):
        for i in range(n):
            depth = render_depth(view, boxes_at(i))
            self.c.request("POST", "/v1/maps/home/scenes/%d/frames?stamp=%d" % (scene, start_ns + i * FRAME_NS), depth)
        self.steps.append("POST /v1/maps/home/scenes/%d/frames x %d (raw uint16)" % (scene, n))

    def write_scenes(self):
        place_a = camera_pose(0.0, 0.0, 1.2, 0.0, math.radians(35))
        place_b = camera_pose(0.0, -0.8, 1.1, 0.2, math.radians(30))
        n, put = 36, 12
        opened = []
        # Visit 1 at A: the box is put down at frame `put`; a manual keyframe after it; closed.
        s1 = self.call("POST", "/v1/maps/home/scenes", {"camera": CAMERA, "pose": place_a[0], "stamp": T0_NS})["id"]
        self.frames(s1, place_a, lambda i: [BOX] if i >= put else [], n // 2, T0_NS)
        self.call("POST", "/v1/maps/home/scenes/%d/keyframes" % s1)
        self.frames(s1, place_a, lambda i: [BOX], n - n // 2, T0_NS + (n // 2) * FRAME_NS)
        self.call("POST", "/v1/maps/home/scenes/%d:close" % s1)
        opened.append(s1)
        t2 = T0_NS + 600 * 10 ** 9
        # Visit 2 at A, ten minutes later: merged with visit 1 (which it supersedes); the box is taken away.
        s2 = self.call("POST", "/v1/maps/home/scenes", {"camera": CAMERA, "pose": place_a[0], "stamp": t2,
                                                        "params": {"beta": 0.03, "dynamic_mode": "subtract"}})["id"]
        self.frames(s2, place_a, lambda i: [BOX] if i < put else [], n, t2)
        self.call("POST", "/v1/maps/home/scenes/%d:close" % s2)
        opened.append(s2)
        # Visit 3 at B (merge off): still observing when the server stops.
        t3 = T0_NS + 900 * 10 ** 9
        s3 = self.call("POST", "/v1/maps/home/scenes", {"camera": CAMERA, "pose": place_b[0], "stamp": t3,
                                                        "merge": False})["id"]
        self.frames(s3, place_b, lambda i: [], 12, t3)
        self.call("POST", "/v1/maps/home/scenes/%d/keyframes" % s3)
        opened.append(s3)
        # A scratch map with a scene and a keyframe, deleted: the largest keyframe id so far is gone, so a
        # migration that rebuilt the table and lost its AUTOINCREMENT sequence would hand that id out again.
        self.call("POST", "/v1/maps", {"id": "scratch"})
        s4 = self.call("POST", "/v1/maps/scratch/scenes", {"camera": CAMERA, "pose": place_b[0], "stamp": t3,
                                                           "merge": False})["id"]
        for i in range(3):
            self.c.request("POST", "/v1/maps/scratch/scenes/%d/frames?stamp=%d" % (s4, t3 + i * FRAME_NS),
                           render_depth(place_b, []))
        self.call("POST", "/v1/maps/scratch/scenes/%d/keyframes" % s4)
        self.call("POST", "/v1/maps/scratch/scenes/%d:close" % s4)
        self.call("DELETE", "/v1/maps/scratch")
        self.expect["deleted_map"] = "scratch"
        self.expect["observing_scene"] = s3
        self.expect["camera"] = CAMERA
        self.expect["place_b_pose"] = place_b[0]
        self.expect["place_b_view"] = [0.2, math.radians(30)]  # yaw, tilt of camera_pose
        self.scene_ids = opened

    def read_scenes(self):
        keyframes = {}
        self.read("/v1/maps/home/scenes?limit=100")
        for s in self.scene_ids:
            scene = self.read("/v1/maps/home/scenes/%d" % s)
            for layer in ("static", "movable", "dynamic", "reliability"):
                self.read("/v1/maps/home/scenes/%d/layers/%s?format=raw" % (s, layer), "bytes")
            for k in scene["keyframes"]:
                kid = k["id"] if isinstance(k, dict) else k
                info = self.read("/v1/maps/home/keyframes/%d" % kid)
                keyframes[str(kid)] = info["kind"]
                self.read("/v1/maps/home/keyframes/%d/depth" % kid, "png")
                self.read("/v1/maps/home/keyframes/%d/background" % kid, "png")
        self.expect["scenes"] = {str(s): self.entries_value("/v1/maps/home/scenes/%d" % s)["status"]
                                 for s in self.scene_ids}
        self.expect["keyframes"] = keyframes

    def entries_value(self, path):
        return next(e["value"] for e in self.entries if e["path"] == path)

    # ------------------------------------------------------------ furniture graphs

    def write_furniture(self):
        room = {"viewpoint": {"position": [0, 0], "heading_rad": 0},
                "furniture": [
                    {"id": "sofa", "position": [4.0, 0.0], "extent": [0.9, 2.0],
                     "categories": {"sofa": 0.6, "armchair": 0.3, "table": 0.1}},
                    {"id": "plant", "position": [4.0, 1.7], "extent": [0.4, 0.4],
                     "categories": {"plant": 0.7, "stool": 0.3}},
                    {"id": "table", "position": [2.8, 0.0], "extent": [0.6, 1.0], "yaw_rad": 0.1,
                     "categories": {"table": 0.6, "stool": 0.2, "chair": 0.2}},
                    {"id": "shelf", "position": [4.2, -1.6], "extent": [0.4, 1.0],
                     "categories": {"armchair": 0.45, "shelf": 0.35, "wardrobe": 0.2}}],
                "params": {"n_best": 50}}
        descriptions = [{"text": "the plant is left of the sofa"},
                        {"located": "table", "relation": "in_front_of", "reference": "sofa"},
                        {"text": "the shelf is to the right of the couch"}]
        g1 = self.call("POST", "/v1/maps/home/furniture-graphs", room)["id"]
        for d in descriptions:
            self.call("POST", "/v1/maps/home/furniture-graphs/%d/descriptions" % g1, d)
        g2 = self.call("POST", "/v1/maps/home/furniture-graphs", dict(room, params={"n_best": 20, "adaptation": False}))["id"]
        for d in descriptions[:2]:
            self.call("POST", "/v1/maps/home/furniture-graphs/%d/descriptions" % g2, d)
        self.call("POST", "/v1/maps/home/furniture-graphs/%d:reset" % g2)
        self.call("POST", "/v1/maps/home/furniture-graphs/%d/descriptions" % g2, descriptions[2])
        self.graphs = ((g1, descriptions), (g2, descriptions[2:]))

    def read_furniture(self):
        self.read("/v1/maps/home/furniture-graphs")
        graphs = {}
        for g, said in self.graphs:
            graph = self.read("/v1/maps/home/furniture-graphs/%d" % g)
            self.read("/v1/maps/home/furniture-graphs/%d/hypotheses?limit=100" % g)
            graphs[str(g)] = {"descriptions": said, "count": graph["descriptions"]}
        self.expect["furniture_graphs"] = graphs

    # ------------------------------------------------------------ events, instances, jobs

    def write_events(self):
        c = self
        table = c.call("POST", "/v1/maps/home/instances", {"kind": "furniture", "label": "table",
                                                           "position": [1.7, 0.0, 0.15], "extent": [1.0, 0.8, 0.3]})
        cup = c.call("POST", "/v1/maps/home/instances", {"kind": "object", "label": "cup",
                                                         "position": [2.2, 0.9, 0.05], "yaw_rad": 0.4})
        spoon = c.call("POST", "/v1/maps/home/instances", {"kind": "object", "label": "spoon",
                                                           "position": [2.0, 1.1, 0.0]})
        c.call("POST", "/v1/maps/home/instances/%d:label" % cup["id"], {"label": "mug", "source": "operator"})
        c.call("POST", "/v1/maps/home/instances/%d:pin" % cup["id"])
        c.call("DELETE", "/v1/maps/home/instances/%d" % spoon["id"])
        self.expect["deleted_instance"] = spoon["id"]
        observed = c.c.request("GET", "/v1/maps/home/events?limit=1000")["events"]
        added = [e for e in observed if e["type"] == "added" and e.get("instance")]
        if added:  # the box of visit 1, seen being put down: what it is comes from dialog
            c.call("POST", "/v1/maps/home/events/%d:label" % added[0]["id"], {"label": "keys", "source": "dialog"})
        if self.has("POST", "/v1/maps/{map}/keyframes/{keyframe}:pin"):
            first, second = [k["id"] for k in c.c.request("GET", "/v1/maps/home/scenes/%d" % self.scene_ids[0])
                             ["keyframes"]][:2]
            c.call("POST", "/v1/maps/home/keyframes/%d:pin" % first)
            c.call("POST", "/v1/maps/home/keyframes/%d:score" % second, {"relevance": 0.8})
            c.call("POST", "/v1/maps/home/keyframes/%d:reanalyse" % first, {"scene": self.scene_ids[1]})
        # Forgetting jobs: a dry run of a strict policy, then a real one that only drops superseded models' state.
        jobs = {}
        for body in ({"dry_run": True, "policy": {"keyframe_max_age_s": 60, "event_max_age_s": 3600}},
                     {"policy": {"superseded_models": True, "keyframe_max_age_s": None, "event_max_age_s": None}}):
            submitted = c.call("POST", "/v1/maps/home:forget", body)
            job = submitted.get("job", submitted.get("id"))
            for _ in range(400):
                state = c.c.request("GET", "/v1/jobs/%d" % job)
                if state["status"] in ("succeeded", "failed"):
                    break
                time.sleep(0.05)
            jobs[str(job)] = state["status"]
        self.expect["jobs"] = jobs

    def read_events(self):
        events = self.read("/v1/maps/home/events?limit=1000")["events"]
        counts = {}
        for e in events:
            counts[e["type"]] = counts.get(e["type"], 0) + 1
            self.read("/v1/maps/home/events/%d" % e["id"])
        instances = (self.read("/v1/maps/home/instances?limit=1000")["instances"] +
                     self.read("/v1/maps/home/instances?status=deleted&limit=1000")["instances"])
        labels = {}
        for i in instances:
            self.read("/v1/maps/home/instances/%d" % i["id"])
            self.read("/v1/maps/home/instances/%d/history" % i["id"])
            labels[str(i["id"])] = i["labels"]
        by_label = {}
        for i in instances:
            for label in i["labels"]:
                by_label.setdefault(label, []).append(i["id"])
        for label in sorted(by_label):
            q = urllib.parse.quote(label)
            self.read("/v1/maps/home/instances?label=%s&limit=1000" % q)
            self.read("/v1/maps/home/where?label=%s" % q, fields=("instance", "present", "position_m"), may_fail=True)
        for job in self.expect["jobs"]:
            self.read("/v1/jobs/%s" % job)
        self.expect["event_counts"] = counts
        self.expect["instance_labels"] = labels
        self.expect["instances_by_label"] = {k: sorted(v) for k, v in by_label.items()}


def sqlite_facts(path):
    """What the file itself says: user_version, the tables, the AUTOINCREMENT sequences, row counts."""
    db = sqlite3.connect(path)
    try:
        facts = {"user_version": db.execute("PRAGMA user_version").fetchone()[0]}
        tables = [r[0] for r in db.execute(
            "SELECT name FROM sqlite_master WHERE type = 'table' AND name NOT LIKE 'sqlite_%' "
            "AND name NOT LIKE '%_rtree_%' ORDER BY name")]
        facts["rows"] = {t: db.execute('SELECT count(*) FROM "%s"' % t).fetchone()[0] for t in tables}
        facts["sequences"] = dict(db.execute("SELECT name, seq FROM sqlite_sequence ORDER BY name").fetchall()) \
            if "sqlite_sequence" in {r[0] for r in db.execute("SELECT name FROM sqlite_master")} else {}
        if "schema_migrations" in tables:
            facts["migrations"] = [r[0] for r in db.execute("SELECT version FROM schema_migrations ORDER BY version")]
        return facts
    finally:
        db.close()


def stop(server):
    code = server.stop()
    if code != 0:
        sys.exit("the server exited with %d on SIGTERM:\n%s" % (code, server.stderr_text()))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--server", required=True, help="the anchordb binary of the old commit")
    ap.add_argument("--commit", required=True, help="the commit it was built from (recorded in the manifest)")
    ap.add_argument("--out", required=True, help="the database file to write (must not exist)")
    args = ap.parse_args()
    out = os.path.abspath(args.out)
    if os.path.exists(out):
        sys.exit("%s exists; remove it first" % out)
    os.environ["ANCHORDB_BIN"] = os.path.abspath(args.server)

    # `token create` makes the file (every migration of that release) and stores the hashed tokens.
    tokens = {role: harness.create_token(out, role) for role in ("reader", "writer", "admin")}
    server = harness.Server(db_path=out)
    try:
        w = Writer(server)
        parts = ["grid"] + [part for part, route in (("scenes", "/v1/maps/{map}/scenes"),
                                                     ("furniture", "/v1/maps/{map}/furniture-graphs"),
                                                     ("events", "/v1/maps/{map}/instances")) if w.has("POST", route)]
        parts += w.later_parts()
        for part in parts:
            getattr(w, "write_" + part)()
        # Read back from the file as the old server finds it after a restart (a graceful stop persists the
        # scene left observing, for one).
        stop(server)
        w.c = server.start()
        for part in parts:
            getattr(w, "read_" + part)()
        version = w.c.request("GET", "/v1/health")
        stop(server)
    finally:
        server.close()
    for suffix in ("-wal", "-shm"):
        if os.path.exists(out + suffix) and os.path.getsize(out + suffix) > 0:
            sys.exit("%s%s was left behind: the file is not checkpointed" % (out, suffix))
    manifest = {
        "commit": args.commit,
        "server_health": version,
        "file": os.path.basename(out),
        "sqlite": sqlite_facts(out),
        "tokens": tokens,
        "routes": sorted("%s %s" % r for r in w.routes),
        "expect": w.expect,
        "steps": w.steps,
        "reads": w.entries,
    }
    with open(os.path.splitext(out)[0] + ".json", "w") as f:
        json.dump(manifest, f, indent=1, sort_keys=True)
        f.write("\n")
    print("%s: %d bytes, schema version %d, %d reads in the manifest" % (
        out, os.path.getsize(out), manifest["sqlite"]["user_version"], len(w.entries)))


if __name__ == "__main__":
    main()
