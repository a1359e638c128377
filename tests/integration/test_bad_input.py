"""Acceptance: every route rejects malformed JSON, wrong types, NaN/inf, non-unit quaternions, unknown ids and
oversized bodies with the documented status and code, and a follow-up read proves nothing changed.

Numbers that overflow a double (1e999) are refused by the JSON parser: 400 invalid_json naming the overflow (the
project's choice, commit 7d88f3e; NaN and Infinity literals are not JSON at all and are invalid_json too).

Table-driven: each case is one request with its expected status, code and (where the API names it) field. After
every case the whole visible state is read back (map list, map, layer list with versions, every layer's raw bytes
and PNG, agents) and compared with the state before."""

import unittest

import harness

from bad_input_cases import (C, CASES, GRAPH, GRAPHS, ID_LENGTH, L, LABEL_LENGTH, MAP, MAX_BODY, MAX_MAP_PIXELS,
                             MAX_POLYGONS, MAX_VERTICES, OBS, OBS_PATH, QUERY_PARAMETERS, SQUARE, obs, padded)


class BadInputTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server = harness.Server(None, extra_args=[
            "--max_body_bytes=%d" % MAX_BODY, "--max_polygons=%d" % MAX_POLYGONS,
            "--max_polygon_vertices=%d" % MAX_VERTICES, "--max_map_pixels=%d" % MAX_MAP_PIXELS])
        c = cls.c = cls.server.client
        try:
            c.create_map("m", "bad input")
            c.import_occupancy("m", "occ", MAP.yaml(), MAP.pgm())
            c.create_layer("m", "prob", {"kind": "probability", "base": "occ"})
            c.create_layer("m", "prob2", {"kind": "probability", "base": "occ"})
            c.create_layer("m", "lab", {"kind": "label", "base": "occ"})
            c.create_layer("m", "fz", {"kind": "fused", "op": "or",
                                       "operands": [{"layer": "prob", "threshold": 0.6}, {"layer": "prob2"}]})
            c.request("POST", OBS_PATH, OBS)
            c.paint_label("m", "lab", "kitchen", [SQUARE])
            c.put_agent("m", "p", [1.0, 1.0], 0.0)
            cls.instance = c.create_instance("m", "table", [1.0, 2.0, 0.0])["id"]
            cls.graph = c.request("POST", GRAPHS, GRAPH)["id"]
        except Exception:
            cls.server.close()
            raise
        cls.results = {}

    @classmethod
    def tearDownClass(cls):
        cls.server.close()

    def snapshot(self):
        c = self.c
        state = {"maps": c.list_maps(), "map": c.get_map("m"), "layers": c.list_layers("m"),
                 "agents": c.list_agents("m"), "instances": c.instances("m"),
                 "graphs": c.request("GET", GRAPHS), 
                 # a refused edit is audited with its status (by design); no successful one may appear
                 "audit": [e for e in c.request("GET", "/v1/audit")["entries"] if e["status"] < 400]}
        for layer in state["layers"]["layers"]:
            name = layer["name"]
            state["raw " + name] = c.get_layer("m", name, "raw")
            state["png " + name] = c.get_layer("m", name, "png")
            state["json " + name] = c.get_layer("m", name, "json", statistics=True)
        return state

    def send(self, case):
        headers = {"Content-Type": case.content_type or "application/json"} if case.body is not None else None
        body = case.body.encode() if isinstance(case.body, str) else case.body
        path = case.path.replace("{instance}", str(self.instance)).replace("{graph}", str(self.graph))
        return self.c.request(case.method, path, body, headers=headers, raw=True)

    def run_cases(self, group):
        before = self.snapshot()
        for case in CASES[group]:
            with self.subTest(case=case.name):
                r = self.send(case)
                self.server.check_alive()
                ctx = "%s %s -> %d %s" % (case.method, case.path, r.status, r.body[:300])
                after = self.snapshot()
                changed = sorted(k for k in set(before) | set(after) if before.get(k) != after.get(k))
                before = after  # blame a change on the case that made it only
                self.assertEqual(r.status, case.status, ctx)
                self.assertTrue(r.headers.get("content-type", "").startswith("application/json"), ctx)
                err = r.json()["error"]
                self.assertIsInstance(err.get("message"), str, ctx)
                self.assertIn("field", err, ctx)
                self.assertEqual(err["code"], case.code, ctx)
                if case.field is not None:
                    self.assertEqual(err["field"], case.field, ctx)
                self.assertEqual(changed, [], "state changed after a rejected request: " + ctx)

    def test_over_limit(self):
        """One over each length limit of strings, arrays and query strings (api/request_limits.h, the settings):
        a clear error naming the field, and nothing changed (instances, graphs and the audit trail included)."""
        self.run_cases("over_limit")

    def test_create_map(self):
        self.run_cases("create_map")

    def test_create_layer_json(self):
        self.run_cases("create_layer_json")

    def test_import_occupancy_multipart(self):
        self.run_cases("import_occupancy_multipart")

    def test_observations(self):
        self.run_cases("observations")

    def test_labels(self):
        self.run_cases("labels")

    def test_regions(self):
        self.run_cases("regions")

    def test_agents(self):
        self.run_cases("agents")

    def test_attention(self):
        self.run_cases("attention")

    def test_viewpoints(self):
        self.run_cases("viewpoints")

    def test_ids_in_the_path(self):
        self.run_cases("ids_in_the_path")

    def test_json_sent_as_form_urlencoded(self):
        """`curl -d` without -H labels a JSON body application/x-www-form-urlencoded. cpp-httplib 0.11 (compiled
        Debian library) caps such bodies at 8192 bytes whatever --max_body_bytes says, so a larger one gets a 413 that
        says how to send it; a small one is handled like JSON. Nothing changes on the refusal."""
        self.c.create_layer("m", "form_prob", {"kind": "probability", "base": "occ"})
        version = self.c.get_layer("m", "form_prob")["version"]
        small = padded(OBS, 2000)
        r = self.c.request("POST", L + "/form_prob/observations", small.encode(),
                           headers={"Content-Type": "application/x-www-form-urlencoded"}, raw=True)
        self.assertEqual(r.status, 200, r.body[:200])
        self.assertEqual(self.c.get_layer("m", "form_prob")["version"], version + 1)
        body = padded(OBS, 10000)
        self.assertLess(len(body), MAX_BODY)
        r = self.c.request("POST", L + "/form_prob/observations", body.encode(),
                           headers={"Content-Type": "application/x-www-form-urlencoded"}, raw=True)
        self.assertEqual(r.status, 413, r.body[:200])
        self.assertIn(b"Content-Type: application/json", r.body)
        self.assertEqual(self.c.get_layer("m", "form_prob")["version"], version + 1)

    def test_read_layer_and_maps(self):
        self.run_cases("read_layer_and_maps")

    def test_overflowing_numbers_are_invalid_json(self):
        """1e999 overflows a double. The parser refuses it (commit 7d88f3e, tests/schema/json_io_test.cc): 400
        invalid_json whose message names the overflow, so the client can tell it from a syntax error."""
        wrong = []
        for group, cases in CASES.items():
            for case in cases:
                if not case.overflow:
                    continue
                r = self.send(case)
                err = r.json().get("error", {}) if r.body else {}
                if (r.status, err.get("code")) != (400, "invalid_json") or "overflow" not in err.get("message", ""):
                    wrong.append("%s/%s: got %d %s %r" % (group, case.name, r.status, err.get("code"),
                                                          err.get("message")))
        self.assertEqual(wrong, [], "\n" + "\n".join(wrong))

    def test_valid_requests_still_work(self):
        """The fixture's valid requests succeed (so the rejections above are about the bad parts only)."""
        c = self.c
        version = c.get_layer("m", "prob")["version"]
        r = self.send(C("valid observation", "POST", L + "/prob2/observations", obs(), 200, None))
        self.assertEqual(r.status, 200, r.body)
        self.assertEqual(c.get_layer("m", "prob2")["version"], 2)
        self.assertEqual(c.get_layer("m", "prob")["version"], version)
        # A quaternion within 1e-3 of unit length is normalised and accepted.
        r = self.send(C("almost unit", "POST", L + "/prob2/observations",
                        obs(**{"pose.orientation": [0, 0, 0, 1.0005]}), 200, None))
        self.assertEqual(r.status, 200, r.body)
        # At the limits (not over them) requests are accepted.
        # (An instance label may be sent with up to LABEL_LENGTH bytes; once normalised it has at most 64 characters.)
        padded_label = " " * (LABEL_LENGTH - 64) + "y" * 64
        at = c.create_instance("m", padded_label, [0.0, 0.0, 0.0])
        self.assertEqual(list(at["labels"]), ["y" * 64])
        self.assertEqual(c.request("GET", "/v1/maps/m/instances?label=" + "y" * 64)["instances"][0]["id"], at["id"])
        self.assertIn("maps", c.request("GET", "/v1/maps?cursor=" + "z" * ID_LENGTH + "&" +
                                        "&".join("p%d=1" % i for i in range(QUERY_PARAMETERS - 1))))


if __name__ == "__main__":
    unittest.main()
