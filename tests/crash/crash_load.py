"""The load of the crash campaign (scripts/crash-campaign): the ledger of acknowledged writes and one function per
writer thread, each on its own keep-alive HTTP/1.1 connection to the server under test."""

import collections
import http.client
import json
import os
import struct
import sys
import threading
import time
import traceback

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path[:0] = [os.path.join(ROOT, "clients", "python"), os.path.join(ROOT, "tests", "integration")]
import anchordb_client  # noqa: E402  (the multipart encoder)
import harness  # noqa: E402  (the synthetic map, poses)

KINDS = ("maps", "layers", "obs", "frames", "keyframes", "analyses", "labels", "pins", "instances")
W, H = 64, 48
CAMERA = {"width": W, "height": H, "fx": 50.0, "fy": 50.0, "cx": 31.5, "cy": 23.5}
MAP = harness.SyntheticMap(40, 30, 0.1, walls=[(20, 1, 20, 15)])
DAY_NS = 86400 * 10**9
OLD_SCENES, OLD_KEYFRAMES_PER_SCENE = 2, 2


def depth_frame(k):
    """A 64x48 uint16 depth frame [mm]: 1500 mm everywhere, a 1000 mm box whose place follows k."""
    depth = [1500] * (W * H)
    x0, y0 = 4 + (k * 3) % 40, 4 + (k * 2) % 28
    for y in range(y0, y0 + 12):
        depth[y * W + x0:y * W + x0 + 12] = [1000] * 12
    return struct.pack("<%dH" % (W * H), *depth)


FRAMES = [depth_frame(k) for k in range(16)]


def rect(x0, y0, x1, y1):
    return [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]


class Killed(Exception):
    """The connection failed after the campaign killed the server: the thread stops."""


class Trial:
    """The shared state of one trial: the server, the ledger of writes, the error list."""

    def __init__(self, server):
        self.server = server
        self.killed = threading.Event()
        self.lock = threading.Lock()
        self.maps, self.layers = set(), {}          # layers: (map, name) -> [base version, acked, unanswered]
        self.label_names = collections.defaultdict(set)  # (map, label layer) -> acknowledged label names
        self.scenes = {}     # (map, id) -> {"acked": frames, "unanswered": frames, "closed": close acknowledged}
        self.keyframes = {}  # (map, id) -> {"pinned": acked pin}
        self.instances = {}  # (map, id) -> {"labels": possible top labels, "pinned": possible states}
        self.old_keyframes = set()
        self.jobs = {}       # "forget" / "backup" -> job id (acknowledged)
        self.acked = collections.Counter()
        self.unexpected = []


class Connection:
    """One keep-alive HTTP/1.1 connection. call() returns (status, json), or None when no answer came (the request
    may or may not have happened); once the server is gone, the next call raises Killed."""

    def __init__(self, trial):
        self.trial = trial
        self.conn = None
        self.dead = False

    def call(self, method, path, body=None, content_type=None, allowed=()):
        headers = {}
        if isinstance(body, (dict, list)):
            body, content_type = json.dumps(body).encode(), "application/json"
        if body is not None:
            headers["Content-Type"] = content_type or "application/octet-stream"
        if self.dead:
            raise Killed()
        try:
            if self.conn is None:
                self.conn = http.client.HTTPConnection("127.0.0.1", self.trial.server.port, timeout=60)
            self.conn.request(method, path, body=body, headers=headers)
            resp = self.conn.getresponse()
            payload = resp.read()
        except (OSError, http.client.HTTPException):
            if self.conn is not None:
                self.conn.close()
            self.conn = None
            self.dead = self.trial.killed.is_set() or not self.trial.server.alive()
            return None
        if resp.status >= 300:
            if resp.status != 503 and resp.status not in allowed:
                with self.trial.lock:
                    self.trial.unexpected.append("%s %s -> %d %s" % (method, path, resp.status, payload[:200]))
            return resp.status, None
        return resp.status, (json.loads(payload) if payload else None)


def ok(answer):
    return answer is not None and answer[0] < 300


def ack(trial, kind):
    with trial.lock:
        trial.acked[kind] += 1


def write_layer(trial, conn, key, method, path, body, kind):
    """A versioned write to one layer (observation or paint); its only writer is the calling thread."""
    state = trial.layers[key]
    answer = conn.call(method, path, body)
    with trial.lock:
        if answer is None:
            state[2] += 1
        elif ok(answer):
            state[1] += 1
            trial.acked[kind] += 1
    return answer


# ------------------------------------------------------------------ the load, one function per thread

def create_map(trial, conn, m):
    """Creates map m until it exists; records it when acknowledged (409: an unanswered attempt created it)."""
    while True:
        answer = conn.call("POST", "/v1/maps", {"id": m}, allowed=(409,))
        if ok(answer):
            trial.maps.add(m)
            ack(trial, "maps")
            return
        if answer is not None and answer[0] == 409:
            return


def grid_load(trial, rng):
    conn, maps, extra = Connection(trial), [], collections.Counter()
    while True:
        if not maps or rng.random() < 0.04:
            m = "grid%d" % len(maps)
            create_map(trial, conn, m)
            body, ctype = anchordb_client._multipart([("yaml", "occ.yaml", "application/yaml", MAP.yaml()),
                                                      ("image", "occ.pgm", "image/x-portable-graymap", MAP.pgm())])
            made = [("occ", conn.call("PUT", "/v1/maps/%s/layers/occ" % m, body, ctype))]
            made.append(("p0", conn.call("PUT", "/v1/maps/%s/layers/p0" % m, {"kind": "probability", "base": "occ"})))
            made.append(("rooms", conn.call("PUT", "/v1/maps/%s/layers/rooms" % m,
                                            {"kind": "label", "base": "occ", "labels": {"1": "kitchen"}})))
            for name, answer in made:
                if ok(answer):
                    trial.layers[(m, name)] = [answer[1]["version"], 0, 0]
                    ack(trial, "layers")
            maps.append(m)
        m = rng.choice(maps)
        r = rng.random()
        if r < 0.6 and (m, "p0") in trial.layers:
            yaw = rng.uniform(-1.0, 1.0)
            x = rng.uniform(1.0, 2.5)
            write_layer(trial, conn, (m, "p0"), "POST", "/v1/maps/%s/layers/p0/observations" % m,
                        {"pose": harness.identity_pose(0.5, 1.5, yaw), "fov_rad": 1.4, "range_m": 3.0,
                         "stimulus": [rect(x, 1.0, x + 0.4, 1.6)]}, "obs")
        elif r < 0.85 and (m, "rooms") in trial.layers:
            label = "room%d" % rng.randrange(6)
            x = rng.uniform(0.2, 3.0)
            answer = write_layer(trial, conn, (m, "rooms"), "POST", "/v1/maps/%s/layers/rooms/labels" % m,
                                 {"label": label, "polygons": [rect(x, 0.5, x + 0.5, 1.2)]}, "labels")
            if ok(answer):
                trial.label_names[(m, "rooms")].add(label)
        elif (m, "occ") in trial.layers:
            extra[m] += 1
            name = "extra%d" % extra[m]
            answer = conn.call("PUT", "/v1/maps/%s/layers/%s" % (m, name), {"kind": "probability", "base": "occ"})
            if ok(answer):
                trial.layers[(m, name)] = [answer[1]["version"], 0, 0]
                ack(trial, "layers")


def open_scene(trial, conn, m, x, stamp_ns=None):
    body = {"camera": CAMERA, "pose": {"position": [x, 0.0, 1.0], "orientation": [0, 0, 0, 1]}, "merge": False}
    if stamp_ns is not None:
        body["stamp"] = stamp_ns
    answer = conn.call("POST", "/v1/maps/%s/scenes" % m, body)
    if not ok(answer):
        return None
    key = (m, answer[1]["id"])
    trial.scenes[key] = {"acked": 0, "unanswered": 0, "closed": False}
    return key


def post_frame(trial, conn, key, k, stamp_ns=None):
    """Posts one frame; returns the answer (its "keyframe" is the begin keyframe of the first frame)."""
    path = "/v1/maps/%s/scenes/%d/frames" % key + ("?stamp=%d" % stamp_ns if stamp_ns is not None else "")
    answer = conn.call("POST", path, FRAMES[k % len(FRAMES)])
    with trial.lock:
        state = trial.scenes[key]
        if answer is None:
            state["unanswered"] += 1
        elif ok(answer):
            state["acked"] += 1
            trial.acked["frames"] += 1
    return answer


def keyframe_of(trial, key, answer, old=False):
    """Records the keyframe an acknowledged answer names (begin, manual or end keyframe)."""
    if ok(answer) and answer[1].get("keyframe") is not None:
        kf = (key[0], answer[1]["keyframe"])
        with trial.lock:
            if old:
                trial.old_keyframes.add(kf)
            else:
                trial.keyframes.setdefault(kf, {"pinned": False})
                trial.acked["analyses"] += 1  # its change analysis, queued with it (crash_check.Check.analyses)
            trial.acked["keyframes"] += 1
        return kf
    return None


def close_scene(trial, conn, key, old=False):
    answer = conn.call("POST", "/v1/maps/%s/scenes/%d:close" % key)
    if ok(answer):
        trial.scenes[key]["closed"] = True
    keyframe_of(trial, key, answer, old)


def scene_load(trial, rng, index):
    conn, m = Connection(trial), "scenes%d" % index
    create_map(trial, conn, m)
    s = 0
    while True:
        s += 1
        key = open_scene(trial, conn, m, 10.0 * s)
        if key is None:
            continue
        for k in range(rng.randint(3, 40)):
            keyframe_of(trial, key, post_frame(trial, conn, key, k + s))
            if rng.random() < 0.08:
                kf = keyframe_of(trial, key, conn.call("POST", "/v1/maps/%s/scenes/%d/keyframes" % key))
                if kf is not None and rng.random() < 0.5 and ok(conn.call("POST", "/v1/maps/%s/keyframes/%d:pin" % kf)):
                    trial.keyframes[kf]["pinned"] = True
                    ack(trial, "pins")
        if rng.random() < 0.8:
            close_scene(trial, conn, key)


def instance_load(trial, rng):
    conn, m = Connection(trial), "things"
    create_map(trial, conn, m)
    made = []
    while True:
        r = rng.random()
        if r < 0.35 or not made:
            label = "thing%d" % rng.randrange(50)
            answer = conn.call("POST", "/v1/maps/%s/instances" % m,
                               {"kind": "furniture", "label": label,
                                "position": [rng.uniform(0, 5), rng.uniform(0, 5), 0.4]})
            if ok(answer):
                key = (m, answer[1]["id"])
                trial.instances[key] = {"labels": {label}, "pinned": {False}, "label_acks": 0, "pin_acks": 0}
                made.append(key)
                ack(trial, "instances")
            continue
        key = rng.choice(made)
        state = trial.instances[key]
        if r < 0.7:
            label = "name%d" % rng.randrange(50)
            answer = conn.call("POST", "/v1/maps/%s/instances/%d:label" % key, {"label": label, "source": "operator"})
            field, value, kind = "labels", label, "label"
        else:
            pin = rng.random() < 0.6
            answer = conn.call("POST", "/v1/maps/%s/instances/%d:%s" % (key[0], key[1], "pin" if pin else "unpin"))
            field, value, kind = "pinned", pin, "pin"
        with trial.lock:
            if answer is None:
                state[field].add(value)
            elif ok(answer):
                state[field] = {value}
                state[kind + "_acks"] += 1
                trial.acked[kind + "s"] += 1


def job_load(trial, rng, forget_at_s, backup_at_s, t0):
    """Old scenes (stamps 20 days ago) in map "old", then a forgetting of them and a backup at the given instants."""
    conn, m = Connection(trial), "old"
    create_map(trial, conn, m)
    start = time.time_ns() - 20 * DAY_NS
    for s in range(OLD_SCENES):
        key = open_scene(trial, conn, m, 100.0 + 10.0 * s, start)
        if key is None:
            continue
        for k in range(OLD_KEYFRAMES_PER_SCENE):
            keyframe_of(trial, key, post_frame(trial, conn, key, k, start + (k + 1) * 10**9), old=True)
            keyframe_of(trial, key, conn.call("POST", "/v1/maps/%s/scenes/%d/keyframes" % key), old=True)
        close_scene(trial, conn, key, old=True)
    plan = sorted([(forget_at_s, "forget"), (backup_at_s, "backup")])
    for at_s, kind in plan:
        time.sleep(max(0.0, t0 + at_s - time.monotonic()))
        if kind == "forget":
            answer = conn.call("POST", "/v1/maps/old:forget",
                               {"policy": {"keyframe_max_age_s": 7 * 86400, "superseded_models": False,
                                           "vacuum": rng.random() < 0.5}})
        else:
            answer = conn.call("POST", "/v1/backups", {"label": "crash"})
        if ok(answer):
            trial.jobs[kind] = answer[1]["job"]
    while True:  # poll the jobs until the kill
        for job in list(trial.jobs.values()):
            conn.call("GET", "/v1/jobs/%d" % job)
        time.sleep(0.01)


def run_thread(trial, target, *args):
    def body():
        try:
            target(trial, *args)
        except Killed:
            pass
        except Exception as e:  # a bug of the campaign itself: fail the trial loudly
            with trial.lock:
                trial.unexpected.append("load thread %s: %s" % (target.__name__, traceback.format_exc()))
    thread = threading.Thread(target=body, daemon=True)
    thread.start()
    return thread
