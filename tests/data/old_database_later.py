"""The parts of make_old_database.py for what schemas 0007-0016 added (Python standard library only).

Each part runs when the server under test has its route (GET /v1/openapi.json), after the parts of the older
schemas, and writes on its own maps or scenes so that what the older parts wrote stays as it was:

  audit        GET /v1/audit (0008): the audit log of every editing action the older parts made, token creation
  analysis     GET /v1/maps/{map}/analysis (0009): the keyframe analysis queue (drained, nothing failed)
  covariance   a scene opened with a ROS pose_covariance (0010), a few frames, closed (from 0015 on, the scene
               of the classify part carries it instead)
  octomap      PUT /v1/maps/{map}/octomap (0011): a tree on the map "living", a PCD room cloud inserted
  features     POST /v1/maps/{map}/features (0012): anchored features of a client type, its codebook, a trained
               E-SAMME classifier
  shapes       POST /v1/shape-models (0013): a shape model trained on two OBJ meshes (a table and a cabinet)
  segment      POST /v1/maps/{map}/furniture:segment (0014): the room cloud segmented into furniture instances
  classify     POST /v1/maps/{map}/instances/{instance}:classify (0015, 0016): a scene at place C where a second box
               appears, fpfh features extracted from its keyframe, the fpfh codebook, a classifier, and the new
               object classified (the classifier's label is a change event since 0016)

The frame journal (0007) needs no part of its own: the scene the scenes part leaves observing has its frames there.
"""

import json
import math
import sys
import time

PCD_STEP_M = 0.03
LIVING_OBJECTS = (((0.2, -0.3, 0.0), (1.0, 0.3, 0.72)),    # a table-sized block
                  ((-1.0, 0.8, 0.0), (-0.5, 1.2, 0.9)))    # a cabinet against the wall
BOX2 = ((1.4, 0.55, 0.0), (1.75, 0.9, 0.28))               # the box that appears at place C


def _g(writer):
    """The generator module that defined the writer's class (make_old_database, or __main__ when run as a script)."""
    return sys.modules[type(writer).__module__]


def box_surface(lo, hi, step):
    """Points on the top and the four sides of an axis-aligned box, `step` apart (the bottom is on the floor)."""
    def axis(a, b):
        n = max(1, int(round((b - a) / step)))
        return [a + (b - a) * i / n for i in range(n + 1)]
    xs, ys, zs = axis(lo[0], hi[0]), axis(lo[1], hi[1]), axis(lo[2], hi[2])
    pts = [(x, y, hi[2]) for x in xs for y in ys]
    pts += [(x, y, z) for x in xs for y in (lo[1], hi[1]) for z in zs[:-1]]
    pts += [(x, y, z) for x in (lo[0], hi[0]) for y in ys[1:-1] for z in zs[:-1]]
    return pts


def room_cloud():
    """The living room (map frame): a 3 x 3 m floor, a wall at y = 1.5 m and the two blocks of LIVING_OBJECTS."""
    step = 0.05
    grid = [i * step for i in range(-30, 31)]
    pts = [(x, y, 0.0) for x in grid for y in grid
           if not any(lo[0] <= x <= hi[0] and lo[1] <= y <= hi[1] for lo, hi in LIVING_OBJECTS)]
    pts += [(x, 1.5, z * step) for x in grid for z in range(1, 31)]
    for lo, hi in LIVING_OBJECTS:
        pts += box_surface(lo, hi, PCD_STEP_M)
    return pts


def pcd_ascii(points):
    head = ("# .PCD v0.7 - made by tests/data/old_database_later.py\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\n"
            "TYPE F F F\nCOUNT 1 1 1\nWIDTH %d\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS %d\nDATA ascii\n"
            % (len(points), len(points)))
    return (head + "".join("%.4f %.4f %.4f\n" % p for p in points)).encode("ascii")


def box_obj(boxes):
    """A Wavefront OBJ (metres, z up) of closed axis-aligned boxes."""
    lines, base = [], 0
    faces = ((1, 3, 2), (1, 4, 3), (5, 6, 7), (5, 7, 8), (1, 2, 6), (1, 6, 5),
             (2, 3, 7), (2, 7, 6), (3, 4, 8), (3, 8, 7), (4, 1, 5), (4, 5, 8))
    for lo, hi in boxes:
        for z in (lo[2], hi[2]):
            for x, y in ((lo[0], lo[1]), (hi[0], lo[1]), (hi[0], hi[1]), (lo[0], hi[1])):
                lines.append("v %.3f %.3f %.3f" % (x, y, z))
        lines += ["f %d %d %d" % tuple(base + i for i in f) for f in faces]
        base += 8
    return ("\n".join(lines) + "\n").encode("ascii")


def table_obj():
    legs = [((x, y, 0.0), (x + 0.05, y + 0.05, 0.68)) for x in (0.0, 0.75) for y in (0.0, 0.55)]
    return box_obj([((0.0, 0.0, 0.68), (0.8, 0.6, 0.72))] + legs)


def cabinet_obj():
    return box_obj([((0.0, 0.0, 0.0), (0.5, 0.4, 0.9))])


def multipart(parts, boundary="anchordb-old-database-boundary"):
    """multipart/form-data of (name, filename or None, content type, bytes); returns (body, Content-Type)."""
    out = bytearray()
    for name, filename, ctype, data in parts:
        out += b"--%s\r\n" % boundary.encode()
        disposition = 'form-data; name="%s"' % name + ('; filename="%s"' % filename if filename else "")
        out += ("Content-Disposition: %s\r\nContent-Type: %s\r\n\r\n" % (disposition, ctype)).encode()
        out += data + b"\r\n"
    out += b"--%s--\r\n" % boundary.encode()
    return bytes(out), "multipart/form-data; boundary=" + boundary


def samples(centres, feature_type, per_class):
    """Deterministic training samples around bags of words: centre + a fixed small offset pattern, clipped at 0."""
    out = []
    for i in range(per_class):
        for label, centre in centres:
            bag = [max(0.0, v + 0.01 * (((i * 7 + w * 3) % 5) - 2)) for w, v in enumerate(centre)]
            out.append({"label": label, "features": {feature_type: bag}})
    return out


class LaterParts:
    """Mixed into make_old_database.Writer: write_<part> and read_<part> for the parts of LATER_PARTS."""

    LATER_PARTS = (("audit", "GET", "/v1/audit"),
                   ("analysis", "GET", "/v1/maps/{map}/analysis"),
                   ("covariance", None, None),
                   ("octomap", "PUT", "/v1/maps/{map}/octomap"),
                   ("features", "POST", "/v1/maps/{map}/features"),
                   ("shapes", "POST", "/v1/shape-models"),
                   ("segment", "POST", "/v1/maps/{map}/furniture:segment"),
                   ("classify", "POST", "/v1/maps/{map}/instances/{instance}:classify"))

    def later_parts(self):
        parts = []
        for part, method, route in self.LATER_PARTS:
            if part == "covariance":  # its own scene only when the classify part's scene cannot carry it
                if self.has_pose_covariance() and not self.has(*self.LATER_PARTS[-1][1:]):
                    parts.append(part)
            elif self.has(method, route):
                parts.append(part)
        return parts

    def wait_job(self, ticket):
        job = ticket.get("job", ticket.get("id"))
        for _ in range(2400):
            state = self.c.request("GET", "/v1/jobs/%d" % job)
            if state["status"] in ("succeeded", "failed"):
                break
            time.sleep(0.05)
        if state["status"] != "succeeded":
            raise RuntimeError("job %d: %s" % (job, state))
        self.expect.setdefault("later_jobs", {})[str(job)] = state["status"]
        return state

    def wait_analysis(self, map_id):
        if not self.has("GET", "/v1/maps/{map}/analysis"):
            time.sleep(2.0)
            return
        for _ in range(1200):
            if self.c.request("GET", "/v1/maps/%s/analysis" % map_id)["depth"] == 0:
                return
            time.sleep(0.05)
        raise RuntimeError("the analysis queue of %s did not drain" % map_id)

    # ------------------------------------------------------------ audit, analysis queue

    def write_audit(self):
        pass  # the older parts' editing actions and `token create` are audited

    def read_audit(self):
        entries = self.read("/v1/audit?limit=1000")["entries"]
        actions = {}
        for e in entries:
            actions[e["action"]] = actions.get(e["action"], 0) + 1
        self.expect["audit_actions"] = actions

    def write_analysis(self):
        self.wait_analysis("home")

    def read_analysis(self):
        self.read("/v1/maps/home/analysis", fields=("failed", "failures"))

    # ------------------------------------------------------------ pose covariance

    def has_pose_covariance(self):
        scene_open = self.openapi.get("components", {}).get("schemas", {}).get("SceneOpen", {})
        return "pose_covariance" in scene_open.get("properties", {})

    def open_scene(self, place, t):
        """A scene at `place` (merge off), with a ROS pose covariance when the server takes one."""
        g = _g(self)
        body = {"camera": g.CAMERA, "pose": place[0], "stamp": t, "merge": False}
        if self.has_pose_covariance():
            cov = [0.0] * 36
            for i, v in enumerate((0.0004, 0.0004, 0.0009, 0.0012, 0.0012, 0.0025)):
                cov[i * 7] = v
            cov[1] = cov[6] = 0.0001  # x-y correlated
            body["pose_covariance"] = cov
        s = self.call("POST", "/v1/maps/home/scenes", body)["id"]
        if self.has_pose_covariance():
            self.expect["covariance_scene"] = {"id": s, "pose_covariance": body["pose_covariance"]}
        return s

    def write_covariance(self):
        g = _g(self)
        place = g.camera_pose(0.0, -0.8, 1.1, 0.2, math.radians(30))
        t = g.T0_NS + 1200 * 10 ** 9
        s = self.open_scene(place, t)
        self.frames(s, place, lambda i: [], 4, t)
        self.call("POST", "/v1/maps/home/scenes/%d:close" % s)

    def read_covariance(self):
        s = self.expect["covariance_scene"]["id"]
        self.read("/v1/maps/home/scenes/%d" % s)
        self.read("/v1/maps/home/scenes/%d/layers/static?format=raw" % s, "bytes")

    # ------------------------------------------------------------ OctoMap

    def write_octomap(self):
        self.call("POST", "/v1/maps", {"id": "living", "name": "Living room"})
        self.call("PUT", "/v1/maps/living/octomap", {"resolution_m": 0.1, "max_range_m": 6.0})
        self.call("POST", "/v1/maps/living/octomap/points?origin=0,-1.2,1.4&stamp=%d" % (_g(self).T0_NS + 3 * 10 ** 12),
                  pcd_ascii(room_cloud()), {"Content-Type": "application/x-pcd"})

    def read_octomap(self):
        info = self.read("/v1/maps/living/octomap?format=json")
        self.read("/v1/maps/living/octomap?format=bt", "bytes")
        self.expect["octomap"] = {"map": "living", "leaves": info.get("leaves")}
        self.expect["maps"]["living"] = "Living room"

    # ------------------------------------------------------------ anchored features, codebook, classifier

    def write_features(self):
        g = _g(self)
        feats = []
        for i in range(12):
            room = i % 2  # two kinds of place: descriptors near (1, 0, 0, 0) or (0, 0, 1, 1)
            d = [1.0, 0.0, 0.0, 0.0] if room == 0 else [0.0, 0.0, 1.0, 1.0]
            d = [round(v + 0.05 * ((i * 3 + k) % 4), 3) for k, v in enumerate(d)]
            feats.append({"descriptor": d, "anchor_m": [0.25 * i, (-0.6 if room == 0 else 0.8), 0.1 * (i % 3)]})
        self.call("POST", "/v1/maps/home/features", {"type": "x_toy", "stamp": g.T0_NS + 2 * 10 ** 12,
                                                     "features": feats})
        self.wait_job(self.call("POST", "/v1/maps/home/codebooks", {"type": "x_toy", "words": 3, "seed": 1}))
        self.wait_job(self.call("POST", "/v1/classifiers", {
            "name": "rooms", "samples": samples([("kitchen", [0.6, 0.3, 0.1]), ("hall", [0.1, 0.3, 0.6])], "x_toy", 6),
            "rounds": 3, "folds": 0, "seed": 2, "base": [{"kind": "knn", "k": 1}, {"kind": "dtree", "max_depth": 2}]}))

    def read_features(self):
        listed = self.read("/v1/maps/home/features?type=x_toy&limit=100")
        self.read("/v1/maps/home/features?type=x_toy&limit=100&descriptors=true")
        self.read("/v1/maps/home/features?near=1.0,-0.6,0.1&radius=0.6&limit=100")
        self.read("/v1/maps/home/codebooks/x_toy")
        self.read("/v1/maps/home/bow?type=x_toy&near=1.5,0,0.1&radius=2")
        self.read("/v1/classifiers")
        self.read("/v1/classifiers/rooms")
        self.expect["features"] = {"type": "x_toy", "count": len(listed["features"]), "classifier": "rooms"}

    # ------------------------------------------------------------ shape models

    def write_shapes(self):
        spec = {"name": "furniture", "params": {"codebook_size": 20, "max_keypoints": 80, "seed": 1},
                "mesh_views": 4, "categories": ["table", "cabinet"],
                "samples": [{"part": "t", "category": "table", "kind": "mesh"},
                            {"part": "c", "category": "cabinet", "kind": "mesh"}]}
        body, ctype = multipart([("spec", None, "application/json", json.dumps(spec, sort_keys=True).encode("utf-8")),
                                 ("t", "table.obj", "text/plain", table_obj()),
                                 ("c", "cabinet.obj", "text/plain", cabinet_obj())])
        self.wait_job(self.call("POST", "/v1/shape-models", body, {"Content-Type": ctype}))

    def read_shapes(self):
        self.read("/v1/shape-models")
        model = self.read("/v1/shape-models/furniture")
        self.expect["shape_model"] = {"name": "furniture", "categories": model.get("categories")}

    # ------------------------------------------------------------ furniture instances from segments

    def write_segment(self):
        if "octomap" not in self.later_parts():
            self.call("POST", "/v1/maps", {"id": "living", "name": "Living room"})
        job = self.wait_job(self.call("POST", "/v1/maps/living/furniture:segment", pcd_ascii(room_cloud()),
                                      {"Content-Type": "application/x-pcd"}))
        self.expect["segment_job"] = job["id"]

    def read_segment(self):
        pieces = self.read("/v1/maps/living/furniture")["furniture"]
        for f in pieces:
            self.read("/v1/maps/living/furniture/%d" % f["id"])
            self.read("/v1/maps/living/furniture/%d/cloud" % f["id"], "bytes")
        self.read("/v1/jobs/%d" % self.expect["segment_job"])
        self.expect["furniture"] = {"map": "living", "count": len(pieces)}
        self.expect["maps"]["living"] = "Living room"

    # ------------------------------------------------------------ classification of an observed object

    def write_classify(self):
        g = _g(self)
        place_c = g.camera_pose(0.0, 0.8, 1.1, -0.2, math.radians(32))
        t = g.T0_NS + 1500 * 10 ** 9
        s = self.open_scene(place_c, t)
        self.frames(s, place_c, lambda i: [BOX2] if i >= 6 else [], 18, t)
        self.call("POST", "/v1/maps/home/scenes/%d:close?wait_for_analysis=true" % s)
        self.wait_analysis("home")
        added = [e for e in self.c.request("GET", "/v1/maps/home/events?type=added&limit=1000")["events"]
                 if e.get("scene") == s and e.get("instance") and e.get("segment")]
        if not added:
            raise RuntimeError("the box at place C made no added event with a segment")
        instance = added[-1]["instance"]
        keyframes = [k["id"] if isinstance(k, dict) else k
                     for k in self.c.request("GET", "/v1/maps/home/scenes/%d" % s)["keyframes"]]
        self.call("POST", "/v1/maps/home/keyframes/%d:extract" % keyframes[-1], {"types": ["spd"]})
        self.wait_job(self.call("POST", "/v1/maps/home/codebooks", {"type": "spd", "words": 4, "seed": 1}))
        self.wait_job(self.call("POST", "/v1/classifiers", {
            "name": "probe", "samples": samples([("flat", [0.25] * 4), ("spike", [1.0, 0.0, 0.0, 0.0])], "spd", 6),
            "rounds": 3, "folds": 0, "seed": 2, "base": [{"kind": "knn", "k": 1}, {"kind": "dtree", "max_depth": 2}]}))
        result = self.call("POST", "/v1/maps/home/instances/%d:classify" % instance, {"classifier": "probe"})
        self.expect["classified"] = {"scene": s, "instance": instance, "keyframe": keyframes[-1],
                                     "label": result.get("label"), "event": result.get("event"),
                                     "applied": result.get("applied")}

    def read_classify(self):
        k = self.expect["classified"]
        self.read("/v1/maps/home/scenes/%d" % k["scene"])
        self.read("/v1/maps/home/scenes/%d/layers/static?format=raw" % k["scene"], "bytes")
        self.read("/v1/maps/home/instances/%d" % k["instance"])
        self.read("/v1/maps/home/features?type=spd&keyframe=%d&limit=20" % k["keyframe"])
        self.read("/v1/maps/home/codebooks/spd")
        self.read("/v1/classifiers/probe")
