"""Seeded random requests against every route of the OpenAPI document: the server never answers 5xx, never dies,
answers every refusal with the JSON error body ({"error": {"code", "message", "field"}}), keeps its log one valid
UTF-8 line per event, and leaves a sound database.

A small valid state is built first (a map with an occupancy layer, a probability layer, a closed scene model with
keyframes, an instance, an agent, a furniture graph), so that many requests reach the handlers' deeper checks
instead of stopping at "unknown map". Then N requests are drawn with random.Random(seed): a route template and
method from openapi.json; path parameters from a pool of valid ids, unknown ids and hostile strings; query
parameters from the names the API uses, with hostile values; a body that is absent, malformed, of the wrong type,
deeply nested, huge-numbered, random bytes, or a structurally plausible JSON object with random values. Deleting the
map is left to the last requests so that the rest keep meeting state.

Environment: ANCHORDB_FUZZ_REQUESTS (default 4000) and ANCHORDB_FUZZ_SEED (default 20261123) to run longer or
differently by hand; a failure prints the seed and the request that broke the rule."""

import http.client
import json
import os
import random
import sqlite3
import struct
import unittest

import harness

REQUESTS = int(os.environ.get("ANCHORDB_FUZZ_REQUESTS", "4000"))
SEED = int(os.environ.get("ANCHORDB_FUZZ_SEED", "20261123"))

W, H = 64, 48
CAMERA = {"width": W, "height": H, "fx": 52.5, "fy": 52.5, "cx": 31.5, "cy": 23.5}
MAP = harness.SyntheticMap(40, 30, 0.1, walls=[(20, 1, 20, 15)], unknown=[(30, 20, 38, 28)])

# Query parameter names the API reads somewhere (and a few it does not).
QUERY_NAMES = ["since", "until", "type", "instance", "scene", "after", "limit", "cursor", "label", "at", "kind",
               "status", "format", "clean", "statistics", "threshold", "min_area_m2", "bbox", "agent", "layer",
               "stamp", "frame", "robot", "png", "unknown_param"]
# Body keys the API reads somewhere.
BODY_KEYS = ["pose", "position", "orientation", "camera", "width", "height", "fx", "fy", "cx", "cy", "stamp",
             "merge", "fov_rad", "range_m", "stimulus", "label", "source", "polygons", "heading_rad", "velocity",
             "kind", "extent", "yaw_rad", "policy", "dry_run", "now", "relevance", "name", "id", "furniture",
             "description", "descriptions", "text", "layer", "threshold", "robot", "agent", "type", "values",
             "resolution_m", "origin", "encoding", "data", "strategy"]


def hostile_strings():
    return ["", "-1", "0", "1", "2", "999999", "99999999999999999999999", "1.5", "1e3", "NaN", "home", "nothere",
            "%2E%2E%2F%2E%2E", "..", "a%00b", "%ZZ", "%C3%A9t%C3%A9", "x" * 300, "%20", "null", "true",
            "occupancy", "people", "movable", "background", "depth"]


def random_scalar(rng):
    return rng.choice([
        0, -1, 1, 2, 7, 3.5, -0.0, 1e308, -1e308, 2 ** 63, -2 ** 63 - 1, 2 ** 64, 1e-320, True, False, None,
        "", "x", "home", "dialog", "operator", "furniture", "object", "2026-11-23T10:00:00Z", "9999-99-99",
        "1970-01-01T00:00:00Z", "\u00e9t\u00e9", "\u0000", "a" * 2000, "NaN", "-inf",
    ])


def random_value(rng, depth=0):
    r = rng.random()
    if depth > 3 or r < 0.45:
        return random_scalar(rng)
    if r < 0.7:
        return [random_value(rng, depth + 1) for _ in range(rng.randint(0, 5))]
    if r < 0.8:  # a vector or a polygon, roughly the right shape
        return [[rng.uniform(-5, 5), rng.uniform(-5, 5)] for _ in range(rng.randint(0, 6))]
    return {rng.choice(BODY_KEYS): random_value(rng, depth + 1) for _ in range(rng.randint(0, 6))}


def random_body(rng):
    """(bytes or None, content type or None)"""
    kind = rng.randrange(12)
    if kind == 0:
        return None, None
    if kind == 1:
        return b"", "application/json"
    if kind == 2:
        return rng.choice([b"{", b"[", b"{\"pose\":", b"nul", b"1e999", b"NaN", b"\"unterminated", b"{}}",
                           b"\xff\xfe\x00", b"[1,2,,]", b"{\"a\":1,\"a\":2}"]), "application/json"
    if kind == 3:  # deep nesting (parser and destructor must not overflow the stack)
        depth = rng.choice([100, 1000, 5000])
        return (b"[" * depth + b"]" * depth), "application/json"
    if kind == 4:
        return bytes(rng.randrange(256) for _ in range(rng.randint(1, 600))), rng.choice(
            ["application/octet-stream", "image/png", "application/json", None])
    if kind == 5:
        return json.dumps(random_scalar(rng)).encode(), "application/json"
    if kind == 6:  # a raw depth frame of the wrong size, or the right size
        n = rng.choice([W * H, W * H - 1, 10, 0])
        return struct.pack("<%dH" % n, *([rng.randrange(65536)] * n)), "application/octet-stream"
    if kind == 7:
        return b"--x\r\nContent-Disposition: form-data; name=\"yaml\"\r\n\r\nimage: a\r\n--x--", \
            rng.choice(["multipart/form-data; boundary=x", "multipart/form-data", "multipart/form-data; boundary="])
    obj = {rng.choice(BODY_KEYS): random_value(rng) for _ in range(rng.randint(1, 8))}
    return json.dumps(obj).encode(), "application/json"


def routes():
    with open(os.path.join(os.path.dirname(__file__), "..", "..", "api", "openapi.json")) as f:
        doc = json.load(f)
    out = []
    for path, ops in doc["paths"].items():
        for method in ops:
            if method in ("get", "post", "put", "delete", "patch"):
                out.append((method.upper(), path))
    return out


class FuzzRoutesTest(unittest.TestCase):
    def setUp(self):
        # Event streams the fuzzer opens end within a second even when the server has not noticed the hang-up.
        self.server = harness.Server(self, extra_args=["--stream_max_duration_s=1"])
        self.c = self.server.client
        c = self.c
        c.create_map("home")
        c.import_occupancy("home", "occupancy", MAP.yaml(), MAP.pgm())
        c.create_layer("home", "people", {"kind": "probability", "base": "occupancy"})
        c.put_agent("home", "person", [1.0, 1.0], 0.0)
        c.create_instance("home", "table", [1.0, 1.0, 0.0], extent=[1.0, 0.6, 0.75])
        pose = {"position": [0.0, 0.0, 1.0], "orientation": [0.0, 0.0, 0.0, 1.0]}
        scene = c.request("POST", "/v1/maps/home/scenes", {"camera": CAMERA, "pose": pose})["id"]
        frame = struct.pack("<%dH" % (W * H), *([1500] * (W * H)))
        for _ in range(2):
            c.request("POST", "/v1/maps/home/scenes/%d/frames" % scene, frame)
        c.request("POST", "/v1/maps/home/scenes/%d/keyframes" % scene)
        c.request("POST", "/v1/maps/home/scenes/%d:close" % scene)

    def send(self, method, path, body, content_type):
        conn = http.client.HTTPConnection("127.0.0.1", self.server.port, timeout=30)
        try:
            headers = {}
            if content_type:
                headers["Content-Type"] = content_type
            conn.request(method, path, body=body, headers=headers)
            resp = conn.getresponse()
            ctype = resp.getheader("Content-Type") or ""
            if ctype.startswith("text/event-stream"):
                # An event stream that opened is an answer: it runs until stream_max_duration_s, so hang up (the
                # server frees the stream at its next poll) instead of reading it to its end.
                return resp.status, ctype, b"", None
            return resp.status, ctype, resp.read(), resp.getheader("Retry-After")
        finally:
            conn.close()

    def test_random_requests_never_crash_or_answer_5xx(self):
        rng = random.Random(SEED)
        table = routes()
        self.assertGreater(len(table), 40)
        statuses = {}
        for n in range(REQUESTS):
            method, template = rng.choice(table)
            late = n >= REQUESTS - REQUESTS // 20
            path = template
            while "{" in path:
                a = path.index("{")
                b = path.index("}", a)
                name = path[a + 1:b]
                if name == "map" and (rng.random() < 0.8 or (method == "DELETE" and template == "/v1/maps/{map}")):
                    value = "home" if not (method == "DELETE" and template == "/v1/maps/{map}" and not late) else "gone"
                elif name == "layer" and rng.random() < 0.6:
                    value = rng.choice(["occupancy", "people", "movable", "background", "depth", "dynamic"])
                elif rng.random() < 0.5:
                    value = rng.choice(["1", "2", "3"])
                else:
                    value = rng.choice(hostile_strings())
                path = path[:a] + value + path[b + 1:]
            if rng.random() < 0.6:
                pairs = ["%s=%s" % (rng.choice(QUERY_NAMES), rng.choice(hostile_strings()))
                         for _ in range(rng.randint(1, 4))]
                path += "?" + "&".join(pairs)
            body, content_type = random_body(rng) if method in ("POST", "PUT", "PATCH") else (None, None)
            where = "seed %d request %d: %s %s (%s, %d body bytes)" % (
                SEED, n, method, path[:200], content_type, len(body or b""))
            try:
                status, ctype, payload, retry_after = self.send(method, path, body, content_type)
            except (ConnectionError, http.client.HTTPException, OSError) as e:
                self.server.check_alive()
                self.fail("%s: no answer (%s)" % (where, e))
            statuses[status] = statuses.get(status, 0) + 1
            if status == 503 and ":stream" in template:
                # Streams the fuzzer hung up on hold their slot until the server's next poll: a stream asked for
                # while every slot is taken is overload, answered as SPEC section 8 says (503 overloaded with
                # Retry-After), which is an answer, not a failure. Anything else at 5xx is.
                self.assertEqual(json.loads(payload)["error"]["code"], "overloaded", where)
                self.assertIsNotNone(retry_after, where)
                continue
            self.assertLess(status, 500, "%s -> %d %r" % (where, status, payload[:300]))
            if status >= 400:
                self.assertIn("application/json", ctype, where)
                err = json.loads(payload)["error"]
                self.assertIsInstance(err["code"], str, where)
                self.assertTrue(err["message"], where)
                self.assertIn("field", err, where)
            if n % 100 == 0:
                self.server.check_alive()
        self.server.check_alive()
        print("fuzz: %d requests, seed %d, statuses %s" % (REQUESTS, SEED, dict(sorted(statuses.items()))))
        # Not only refusals: some requests must have been accepted, else the generator tests nothing deep.
        self.assertGreater(sum(v for k, v in statuses.items() if k < 300), REQUESTS // 20)
        self.server.stop()
        # The log stays one line per event and valid UTF-8 whatever the requests carried (decoded paths, messages
        # quoting bodies): no forged lines, nothing a log reader chokes on.
        with open(self.server._stderr_path, "rb") as f:
            log = f.read().decode("utf-8")  # raises on malformed UTF-8
        lines = log.splitlines()
        self.assertGreater(len(lines), REQUESTS // 2)
        for line in lines:
            self.assertRegex(line, r"^\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d", "log line not from the server: %r" % line[:200])
        con = sqlite3.connect(self.server.db_path)
        try:
            self.assertEqual(con.execute("PRAGMA integrity_check").fetchone()[0], "ok")
            self.assertEqual(con.execute("PRAGMA foreign_key_check").fetchall(), [])
        finally:
            con.close()


if __name__ == "__main__":
    unittest.main()
