"""API conventions of SPEC section 5 over loopback HTTP: health, settings, Prometheus metrics, request ids, JSON
errors for unknown routes and for bodies over --max_body_bytes, and the OpenAPI document covering every route."""

import glob
import http.client
import json
import os
import re
import unittest

import harness

MAX_BODY = 4096
API_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "api")

# One Prometheus sample line: name{labels} value [timestamp]
SAMPLE = re.compile(r'^([a-zA-Z_:][a-zA-Z0-9_:]*)(\{(?:[a-zA-Z_][a-zA-Z0-9_]*="(?:[^"\\]|\\.)*",?)*\})?'
                    r' (-?[0-9.eE+-]+|NaN|\+Inf|-Inf)( -?[0-9]+)?$')


def parse_prometheus(text):
    """{(name, frozenset(labels.items())): value}; fails on any line that is not valid text exposition."""
    samples = {}
    for line in text.splitlines():
        if not line.strip():
            continue
        if line.startswith("#"):
            if not re.match(r"^# (HELP|TYPE) [a-zA-Z_:][a-zA-Z0-9_:]* .+$", line):
                raise AssertionError("bad comment line in /metrics: %r" % line)
            continue
        m = SAMPLE.match(line)
        if not m:
            raise AssertionError("bad sample line in /metrics: %r" % line)
        labels = dict(re.findall(r'([a-zA-Z_][a-zA-Z0-9_]*)="((?:[^"\\]|\\.)*)"', m.group(2) or ""))
        samples[(m.group(1), frozenset(labels.items()))] = float(m.group(3))
    return samples


def route_requests(samples, route):
    """Sum of anchordb_http_requests_total over statuses for one route key ("GET /v1/maps")."""
    return sum(v for (name, labels), v in samples.items()
               if name == "anchordb_http_requests_total" and dict(labels).get("route") == route)


class ApiConventionsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server = harness.Server(None, extra_args=["--max_body_bytes=%d" % MAX_BODY])
        cls.c = cls.server.client

    @classmethod
    def tearDownClass(cls):
        cls.server.close()

    def tearDown(self):
        self.server.check_alive()

    def test_health(self):
        r = self.c.request("GET", "/v1/health", raw=True)
        self.assertEqual(r.status, 200)
        self.assertTrue(r.headers["content-type"].startswith("application/json"))
        self.assertEqual(r.json(), {"status": "ok"})

    def test_settings_lists_every_setting_with_description_and_value(self):
        doc = self.c.settings()
        settings = {s["name"]: s for s in doc["settings"]}
        # Every setting `serve --help` documents is listed, and nothing else.
        help_text = harness.run_cli(["serve", "--help"]).stdout
        documented = set(re.findall(r"^\s+--([a-z_0-9]+)=<", help_text, re.M))
        self.assertGreater(len(documented), 10, help_text)
        self.assertEqual(set(settings), documented)
        for name, s in settings.items():
            self.assertIn("description", s, name)
            self.assertIsInstance(s["description"], str, name)
            self.assertGreater(len(s["description"]), 5, name)
            self.assertIn("value", s, name)
        # Values are the running server's, not the defaults.
        self.assertEqual(settings["max_body_bytes"]["value"], MAX_BODY)
        self.assertEqual(settings["port"]["value"], 0)
        self.assertEqual(settings["bind"]["value"], "127.0.0.1")
        self.assertEqual(settings["db"]["value"], self.server.db_path)

    def test_metrics_is_prometheus_text_and_counts_requests(self):
        r = self.c.request("GET", "/metrics", raw=True)
        self.assertEqual(r.status, 200)
        self.assertTrue(r.headers["content-type"].startswith("text/plain"), r.headers)
        before = route_requests(parse_prometheus(r.body.decode()), "GET /v1/maps")
        for _ in range(3):
            self.c.list_maps()
        after_samples = parse_prometheus(self.c.metrics_text())
        self.assertEqual(route_requests(after_samples, "GET /v1/maps"), before + 3)
        # Errors are counted under their status too.
        def not_found(samples):
            return sum(v for (name, labels), v in samples.items()
                       if name == "anchordb_http_requests_total" and dict(labels).get("route") == "GET /v1/maps/{map}"
                       and dict(labels).get("status") == "404")
        before = not_found(after_samples)
        with self.assertRaises(harness.anchordb_client.ApiError):
            self.c.get_map("no-such-map")
        samples = parse_prometheus(self.c.metrics_text())
        self.assertEqual(not_found(samples), before + 1)
        # A histogram of latencies exists for the route.
        self.assertTrue(any(name.endswith("_bucket") and dict(labels).get("route") == "GET /v1/maps"
                            for (name, labels) in samples), "no latency histogram for GET /v1/maps")

    def _assert_request_id(self, r, what):
        self.assertIn("x-request-id", r.headers, "%s: response (status %d) has no X-Request-Id; headers %s" % (
            what, r.status, r.headers))
        self.assertRegex(r.headers["x-request-id"], r"^[A-Za-z0-9_.-]{1,64}$")

    def test_every_response_has_a_request_id(self):
        cases = [
            ("GET /v1/health", self.c.request("GET", "/v1/health", raw=True)),
            ("POST /v1/maps 201", self.c.request("POST", "/v1/maps", {"id": "rid"}, raw=True)),
            ("POST /v1/maps 409", self.c.request("POST", "/v1/maps", {"id": "rid"}, raw=True)),
            ("POST /v1/maps invalid json", self.c.request("POST", "/v1/maps", "{", raw=True)),
            ("GET unknown map", self.c.request("GET", "/v1/maps/nope", raw=True)),
            ("GET /metrics", self.c.request("GET", "/metrics", raw=True)),
            ("GET unknown route", self.c.request("GET", "/v1/no/such/route", raw=True)),
            ("POST over max_body_bytes", self.c.request("POST", "/v1/maps", {"id": "x" * (2 * MAX_BODY)}, raw=True)),
        ]
        missing = []
        for what, r in cases:
            if "x-request-id" not in r.headers:
                missing.append("%s (status %d)" % (what, r.status))
            else:
                self._assert_request_id(r, what)
        self.assertEqual(missing, [], "responses without X-Request-Id")

    def test_request_id_sent_by_the_client_is_echoed(self):
        r = self.c.request("GET", "/v1/health", headers={"X-Request-Id": "robot-42.a_b"}, raw=True)
        self.assertEqual(r.headers.get("x-request-id"), "robot-42.a_b")
        # Unsafe ids are replaced, never echoed.
        r = self.c.request("GET", "/v1/health", headers={"X-Request-Id": "a b<script>"}, raw=True)
        self.assertNotEqual(r.headers.get("x-request-id"), "a b<script>")
        self._assert_request_id(r, "unsafe id")

    def _assert_json_error(self, r, status, code):
        self.assertEqual(r.status, status, r.body)
        self.assertTrue(r.headers.get("content-type", "").startswith("application/json"), r.headers)
        err = r.json()["error"]
        self.assertEqual(err["code"], code, err)
        self.assertIsInstance(err["message"], str)
        self.assertTrue(err["message"])
        self.assertIn("field", err)
        return err

    def test_unknown_route_is_a_404_json_error(self):
        for method, path in [("GET", "/v1/no/such/route"), ("GET", "/v2/maps"), ("DELETE", "/v1/maps"),
                             ("POST", "/v1/health"), ("GET", "/")]:
            with self.subTest(method=method, path=path):
                self._assert_json_error(self.c.request(method, path, raw=True), 404, "not_found")

    def test_body_over_max_body_bytes_is_413(self):
        maps_before = self.c.list_maps()
        r = self.c.request("POST", "/v1/maps", {"id": "big", "name": "n" * (MAX_BODY + 10)}, raw=True)
        self._assert_json_error(r, 413, "payload_too_large")
        r = self.c.request("PUT", "/v1/maps/big/layers/x", b"\0" * (MAX_BODY * 4),
                           headers={"Content-Type": "application/octet-stream"}, raw=True)
        self._assert_json_error(r, 413, "payload_too_large")
        self.assertEqual(self.c.list_maps(), maps_before)
        # Just under the limit is accepted.
        body = json.dumps({"id": "small", "name": "n" * 200})
        self.assertEqual(self.c.request("POST", "/v1/maps", body, raw=True).status, 201)
        self.c.delete_map("small")

    def test_chunked_body_over_max_body_bytes_is_413(self):
        """The limit must hold for Transfer-Encoding: chunked too (no Content-Length to check up front)."""
        maps_before = self.c.list_maps()
        conn = http.client.HTTPConnection("127.0.0.1", self.server.port, timeout=30)
        try:
            # Valid JSON padded with whitespace: a server that ignores the limit creates the map.
            body = (json.dumps({"id": "chunked", "name": "chunked"}) + " " * (MAX_BODY * 4)).encode()
            chunks = (body[i:i + 1000] for i in range(0, len(body), 1000))
            conn.request("POST", "/v1/maps", body=chunks, headers={"Content-Type": "application/json"},
                         encode_chunked=True)
            resp = conn.getresponse()
            status, payload = resp.status, resp.read()
        finally:
            conn.close()
        maps_after = self.c.list_maps()
        if status == 201:
            self.c.delete_map("chunked")
        self.assertEqual(status, 413, "a %d-byte chunked body passed --max_body_bytes=%d: %s" % (
            len(body), MAX_BODY, payload[:200]))
        self.assertEqual(json.loads(payload)["error"]["code"], "payload_too_large")
        self.assertEqual(maps_after, maps_before)

    def test_openapi_describes_every_route(self):
        doc = self.c.openapi()
        self.assertTrue(doc["openapi"].startswith("3."), doc.get("openapi"))
        routes = []
        for name in sorted(glob.glob(os.path.join(API_DIR, "*.cc"))):  # routes.cc, scene_routes.cc, ...
            with open(name) as f:
                routes += re.findall(r'\bAdd\("(GET|POST|PUT|DELETE)", "([^"]+)"', f.read())
        self.assertGreater(len(routes), 15)
        missing = [(m, p) for m, p in routes if m.lower() not in doc["paths"].get(p, {})]
        self.assertEqual(missing, [], "routes of api/*.cc missing from /v1/openapi.json")
        extra = [(m.upper(), p) for p, ops in doc["paths"].items() for m in ops
                 if m in ("get", "post", "put", "delete", "patch") and (m.upper(), p) not in routes]
        self.assertEqual(extra, [], "operations in /v1/openapi.json that api/*.cc does not serve")


if __name__ == "__main__":
    unittest.main()
