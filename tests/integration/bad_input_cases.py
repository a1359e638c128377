"""The case table of test_bad_input.py: per route group, bad requests with the status, code and (where the API
names it) field they must get. The cases are built against the server limits below (the test starts the server
with them) and refer to the fixture the test creates: map "m" with the occupancy layer "occ" (MAP), probability
layers "prob" and "prob2", label layer "lab", fused layer "fz", and agent "p"."""

import json

import anchordb_client
import harness

MAX_BODY = 16384
MAX_POLYGONS = 4
MAX_VERTICES = 16
MAX_MAP_PIXELS = 2000
# The fixed request limits of api/request_limits.h (the settings above are set by the test).
ID_LENGTH, NAME_LENGTH, LABEL_LENGTH, WORD_LENGTH = 64, 256, 256, 32
CATEGORIES_PER_PIECE, CATEGORY_WORD_LENGTH, DESCRIPTION_WORD_LENGTH = 64, 64, 64
FUSED_OPERANDS, QUERY_VALUE_LENGTH, QUERY_PARAMETERS = 16, 1024, 64
MAX_FURNITURE, MAX_TEXT_LENGTH = 64, 500  # settings grounding_max_furniture, grounding_max_text_length (defaults)

MAP = harness.SyntheticMap(40, 30, 0.1, origin=(-1.0, -1.0, 0.0), walls=[(20, 1, 20, 15)],
                           unknown=[(30, 20, 38, 28)])

# A valid observation: sensor at (0.5, 0.5) looking along +x, a small stimulus square.
SQUARE = [[0.9, 0.2], [1.2, 0.2], [1.2, 0.5], [0.9, 0.5]]
OBS = {"pose": {"position": [0.5, 0.5, 0.0], "orientation": [0, 0, 0, 1]}, "fov_rad": 1.0, "range_m": 2.0,
       "stimulus": [SQUARE]}


def obs(**changes):
    body = json.loads(json.dumps(OBS))
    for key, value in changes.items():
        if key.startswith("pose."):
            body["pose"][key[5:]] = value
        elif value is None:
            body.pop(key)
        else:
            body[key] = value
    return json.dumps(body)


def padded(body_dict, size):
    """Valid JSON of at least `size` bytes (whitespace padding): accepted if the limit were not enforced."""
    text = json.dumps(body_dict)
    return text + " " * max(0, size - len(text))


def multipart(yaml=None, image=None, extra=None):
    parts = []
    if yaml is not None:
        parts.append(("yaml", "map.yaml", "application/yaml", yaml))
    if image is not None:
        parts.append(("image", "map.pgm", "image/x-portable-graymap", image))
    for p in extra or []:
        parts.append(p)
    return anchordb_client._multipart(parts)


class Case:
    def __init__(self, name, method, path, body, status, code, field=None, overflow=False, content_type=None):
        self.name, self.method, self.path, self.body = name, method, path, body
        self.status, self.code, self.field, self.overflow = status, code, field, overflow
        self.content_type = content_type


def C(name, method, path, body, status, code, field=None, **kw):
    return Case(name, method, path, body, status, code, field, **kw)


def MP(name, path, mp, status, code, field=None):
    body, content_type = mp
    return Case(name, "PUT", path, body, status, code, field, content_type=content_type)


BIG_MAP = harness.SyntheticMap(50, 50, 0.1)
TRUNCATED_PGM = MAP.pgm()[:-100]

L = "/v1/maps/m/layers"
OBS_PATH = L + "/prob/observations"
LABEL_PATH = L + "/lab/labels"
AGENT_PATH = "/v1/maps/m/agents/p2"
VP_PATH = "/v1/maps/m/viewpoints"
VP = {"robot": [0.5, 0.5], "agent": "p", "layer": "prob"}


def vp(**changes):
    body = dict(VP)
    body.update(changes)
    return json.dumps(body)


def yaml_with(**changes):
    values = harness.parse_map_yaml(MAP.yaml())
    text = ""
    keys = ["image", "resolution", "origin", "negate", "occupied_thresh", "free_thresh"] + [
        k for k in changes if k not in values]
    for k in keys:
        v = changes.get(k, values.get(k))
        if v is None:
            continue
        if isinstance(v, list):
            v = "[%s]" % ", ".join(repr(x) for x in v)
        text += "%s: %s\n" % (k, v)
    return text.encode()


# A furniture graph the fixture creates (graph "{graph}"), and pieces to build over-long ones from.
PIECE = {"position": [1.0, 0.0], "extent": [0.5, 0.5], "categories": {"table": 0.7, "chair": 0.3}}
GRAPH = {"viewpoint": {"position": [0, 0], "heading_rad": 0},
         "furniture": [dict(PIECE, id="t"), dict(PIECE, id="s", position=[1.0, 1.5], categories={"shelf": 1.0})]}
GRAPHS = "/v1/maps/m/furniture-graphs"


def graph(**changes):
    body = json.loads(json.dumps(GRAPH))
    body.update(changes)
    return json.dumps(body)


def long(n):
    return "x" * n


OVER_LIMIT = [
    # One over each limit of api/request_limits.h and of the settings, on a representative set of routes; the
    # path placeholders {instance} and {graph} are the fixture's.
    C("map name", "POST", "/v1/maps", json.dumps({"id": "lim", "name": long(NAME_LENGTH + 1)}), 400,
      "invalid_argument", "name"),
    C("map id", "POST", "/v1/maps", json.dumps({"id": long(ID_LENGTH + 1)}), 400, "invalid_argument", "id"),
    C("instance label", "POST", "/v1/maps/m/instances",
      json.dumps({"label": long(LABEL_LENGTH + 1), "position": [0, 0, 0]}), 400, "invalid_argument", "label"),
    C("instance kind", "POST", "/v1/maps/m/instances",
      json.dumps({"kind": long(WORD_LENGTH + 1), "label": "a", "position": [0, 0, 0]}), 400, "invalid_argument",
      "kind"),
    C("relabel", "POST", "/v1/maps/m/instances/{instance}:label", json.dumps({"label": long(LABEL_LENGTH + 1)}), 400,
      "invalid_argument", "label"),
    C("relabel source", "POST", "/v1/maps/m/instances/{instance}:label",
      json.dumps({"label": "keys", "source": long(WORD_LENGTH + 1)}), 400, "invalid_argument", "source"),
    C("event label", "POST", "/v1/maps/m/events/1:label", json.dumps({"label": long(LABEL_LENGTH + 1)}), 400,
      "invalid_argument", "label"),
    C("painted label", "POST", LABEL_PATH, json.dumps({"label": long(LABEL_LENGTH + 1), "polygons": [SQUARE]}), 400,
      "invalid_argument", "label"),
    C("label layer name", "PUT", L + "/newlab",
      json.dumps({"kind": "label", "base": "occ", "labels": {"1": long(LABEL_LENGTH + 1)}}), 400, "invalid_argument",
      "labels.1"),
    C("stimulus polygons", "POST", OBS_PATH, obs(stimulus=[SQUARE] * (MAX_POLYGONS + 1)), 413, "payload_too_large",
      "stimulus"),
    C("stimulus vertices", "POST", OBS_PATH, obs(stimulus=[[[0.9 + 0.001 * i, 0.2 + 0.01 * (i % 2)]
                                                          for i in range(MAX_VERTICES + 1)]]), 413,
      "payload_too_large", "stimulus[0]"),
    C("fused operands", "PUT", L + "/newf",
      json.dumps({"kind": "fused", "op": "or", "operands": [{"layer": "prob"}] * (FUSED_OPERANDS + 1)}), 400,
      "invalid_argument", "operands"),
    C("furniture pieces", "POST", GRAPHS,
      graph(furniture=[dict(PIECE, position=[float(i), 0.0]) for i in range(MAX_FURNITURE + 1)]), 413,
      "payload_too_large", "furniture"),
    C("categories of a piece", "POST", GRAPHS,
      graph(furniture=[dict(PIECE, categories={"w%d" % i: 0.01 for i in range(CATEGORIES_PER_PIECE + 1)}),
                       GRAPH["furniture"][1]]), 413, "payload_too_large", "furniture[0].categories"),
    C("category word", "POST", GRAPHS,
      graph(furniture=[dict(PIECE, categories={long(CATEGORY_WORD_LENGTH + 1): 1.0}), GRAPH["furniture"][1]]), 400,
      "invalid_argument", "furniture[0].categories"),
    C("piece id", "POST", GRAPHS, graph(furniture=[dict(PIECE, id=long(ID_LENGTH + 1)), GRAPH["furniture"][1]]), 400,
      "invalid_argument", "furniture[0].id"),
    C("description text", "POST", GRAPHS + "/{graph}/descriptions", json.dumps({"text": long(MAX_TEXT_LENGTH + 1)}),
      400, "invalid_argument", "text"),
    C("description word", "POST", GRAPHS + "/{graph}/descriptions",
      json.dumps({"located": long(DESCRIPTION_WORD_LENGTH + 1), "relation": "left_of", "reference": "shelf"}), 400,
      "invalid_argument", "located"),
    C("scene mode", "POST", "/v1/maps/m/scenes",
      json.dumps({"camera": {"width": 64, "height": 48, "fx": 60, "fy": 60, "cx": 32, "cy": 24},
                  "pose": {"position": [0, 0, 1], "orientation": [0, 0, 0, 1]},
                  "params": {"dynamic_mode": long(WORD_LENGTH + 1)}}), 400, "invalid_argument", "params.dynamic_mode"),
    C("label= query", "GET", "/v1/maps/m/instances?label=" + long(LABEL_LENGTH + 1), None, 400, "invalid_argument",
      "label"),
    C("where label= query", "GET", "/v1/maps/m/where?label=" + long(LABEL_LENGTH + 1), None, 400, "invalid_argument",
      "label"),
    C("any query value", "GET", "/v1/maps?cursor=" + long(QUERY_VALUE_LENGTH + 1), None, 400, "invalid_argument",
      "cursor"),
    C("query parameters", "GET", "/v1/maps?" + "&".join("p%d=1" % i for i in range(QUERY_PARAMETERS + 1)), None, 413,
      "payload_too_large"),
    C("audit actor= query", "GET", "/v1/audit?actor=" + long(ID_LENGTH + 1), None, 400, "invalid_argument", "actor"),
]

CASES = {
    "over_limit": OVER_LIMIT,
    "create_map": [
        C("truncated json", "POST", "/v1/maps", '{"id":', 400, "invalid_json"),
        C("empty body", "POST", "/v1/maps", "", 400, "invalid_json"),
        C("NaN", "POST", "/v1/maps", '{"id": "n1", "name": NaN}', 400, "invalid_json"),
        C("id wrong type", "POST", "/v1/maps", '{"id": 5}', 400, "invalid_argument", "id"),
        C("name wrong type", "POST", "/v1/maps", '{"id": "n2", "name": ["x"]}', 400, "invalid_argument", "name"),
        C("name 1e999", "POST", "/v1/maps", '{"id": "n3", "name": 1e999}', 400, "invalid_json",
          overflow=True),
        C("id with a space", "POST", "/v1/maps", '{"id": "a b"}', 400, "invalid_argument", "id"),
        C("id missing", "POST", "/v1/maps", '{"name": "x"}', 400, "invalid_argument", "id"),
        C("unknown key", "POST", "/v1/maps", '{"id": "n4", "colour": "red"}', 400, "invalid_argument", "colour"),
        C("existing id", "POST", "/v1/maps", '{"id": "m"}', 409, "conflict"),
        C("oversized", "POST", "/v1/maps", padded({"id": "n5"}, MAX_BODY + 100), 413, "payload_too_large"),
    ],
    "create_layer_json": [
        C("truncated json", "PUT", L + "/newl", '{"kind": "probability",', 400, "invalid_json"),
        C("NaN", "PUT", L + "/newl", '{"kind": "probability", "base": "occ", "log_odds": {"hit": NaN}}',
          400, "invalid_json"),
        C("kind wrong type", "PUT", L + "/newl", '{"kind": 1}', 400, "invalid_argument", "kind"),
        C("unknown kind", "PUT", L + "/newl", '{"kind": "voxel"}', 400, "invalid_argument", "kind"),
        C("base wrong type", "PUT", L + "/newl", '{"kind": "probability", "base": ["occ"]}', 400,
          "invalid_argument", "base"),
        C("hit wrong type", "PUT", L + "/newl", '{"kind": "probability", "base": "occ", "log_odds": {"hit": "0.7"}}',
          400, "invalid_argument", "log_odds.hit"),
        C("hit 1e999", "PUT", L + "/newl", '{"kind": "probability", "base": "occ", "log_odds": {"hit": 1e999}}',
          400, "invalid_json", overflow=True),
        C("hit out of range", "PUT", L + "/newl", '{"kind": "probability", "base": "occ", "log_odds": {"hit": 1.5}}',
          422, "unprocessable", "log_odds.hit"),
        C("threshold wrong type", "PUT", L + "/newf",
          '{"kind": "fused", "op": "and", "operands": [{"layer": "prob", "threshold": "high"}, {"layer": "prob2"}]}',
          400, "invalid_argument", "operands[0].threshold"),
        C("threshold -1e999", "PUT", L + "/newf",
          '{"kind": "fused", "op": "and", "operands": [{"layer": "prob", "threshold": -1e999}, {"layer": "prob2"}]}',
          400, "invalid_json", overflow=True),
        C("unknown op", "PUT", L + "/newf",
          '{"kind": "fused", "op": "nand", "operands": [{"layer": "prob"}, {"layer": "prob2"}]}',
          400, "invalid_argument", "op"),
        C("one operand", "PUT", L + "/newf", '{"kind": "fused", "op": "and", "operands": [{"layer": "prob"}]}',
          400, "invalid_argument", "operands"),
        C("unknown operand", "PUT", L + "/newf",
          '{"kind": "fused", "op": "and", "operands": [{"layer": "prob"}, {"layer": "ghost"}]}', 404, "not_found"),
        C("unknown base", "PUT", L + "/newl", '{"kind": "probability", "base": "ghost"}', 404, "not_found"),
        C("base not occupancy", "PUT", L + "/newl", '{"kind": "probability", "base": "prob"}', 422,
          "unprocessable", "base"),
        C("label id 0", "PUT", L + "/newl", '{"kind": "label", "base": "occ", "labels": {"0": "hall"}}', 400,
          "invalid_argument"),
        C("unknown map", "PUT", "/v1/maps/ghost/layers/newl", '{"kind": "probability", "base": "occ"}', 404,
          "not_found", "map"),
        C("existing layer", "PUT", L + "/prob", '{"kind": "probability", "base": "occ"}', 409, "conflict"),
        C("oversized", "PUT", L + "/newl", padded({"kind": "probability", "base": "occ"}, MAX_BODY + 100), 413,
          "payload_too_large"),
    ],
    "import_occupancy_multipart": [
        MP("yaml part missing", L + "/newocc", multipart(image=MAP.pgm()), 400, "invalid_argument", "yaml"),
        MP("image part missing", L + "/newocc", multipart(yaml=MAP.yaml()), 400, "invalid_argument", "image"),
        MP("yaml does not parse", L + "/newocc", multipart(b"resolution: [0.1\norigin: {", MAP.pgm()), 400,
           "invalid_argument", "yaml"),
        MP("yaml resolution wrong type", L + "/newocc", multipart(yaml_with(resolution="fine"), MAP.pgm()), 400,
           "invalid_argument", "yaml.resolution"),
        MP("yaml resolution .inf", L + "/newocc", multipart(yaml_with(resolution=".inf"), MAP.pgm()), 400,
           "invalid_argument", "yaml.resolution"),
        MP("yaml origin .nan", L + "/newocc", multipart(yaml_with(origin="[.nan, 0.0, 0.0]"), MAP.pgm()), 400,
           "invalid_argument", "yaml.origin"),
        MP("yaml origin too short", L + "/newocc", multipart(yaml_with(origin=[0.0, 0.0]), MAP.pgm()), 400,
           "invalid_argument", "yaml.origin"),
        MP("yaml resolution negative", L + "/newocc", multipart(yaml_with(resolution=-0.1), MAP.pgm()), 422,
           "unprocessable", "yaml.resolution"),
        MP("yaml thresholds swapped", L + "/newocc",
           multipart(yaml_with(occupied_thresh=0.1, free_thresh=0.9), MAP.pgm()), 422, "unprocessable"),
        MP("yaml mode is a list", L + "/newocc", multipart(yaml_with(mode="[1, 2]"), MAP.pgm()), 400,
           "invalid_argument", "yaml.mode"),
        MP("yaml mode unknown", L + "/newocc", multipart(yaml_with(mode="fuzzy"), MAP.pgm()), 400,
           "invalid_argument", "yaml.mode"),
        MP("yaml key is a list", L + "/newocc", multipart(b"? [a, b]\n: 1\n" + MAP.yaml(), MAP.pgm()), 400,
           "invalid_argument", "yaml"),
        Case("multipart without boundary", "PUT", L + "/newocc", b"--x\r\nnot a form\r\n", 400, "invalid_argument",
             content_type="multipart/form-data"),
        MP("yaml is a list", L + "/newocc", multipart(b"- 1\n- 2\n", MAP.pgm()), 400, "invalid_argument", "yaml"),
        MP("image garbage", L + "/newocc", multipart(MAP.yaml(), b"GIF89a not a map"), 400, "invalid_argument",
           "image"),
        MP("image truncated", L + "/newocc", multipart(MAP.yaml(), TRUNCATED_PGM), 400, "invalid_argument", "image"),
        MP("image too many pixels", L + "/newocc", multipart(MAP.yaml(), BIG_MAP.pgm()), 413, "payload_too_large",
           "image"),
        MP("png too many pixels", L + "/newocc", multipart(MAP.yaml(), BIG_MAP.png()), 413, "payload_too_large",
           "image"),
        MP("unknown map", "/v1/maps/ghost/layers/newocc", multipart(MAP.yaml(), MAP.pgm()), 404, "not_found", "map"),
        MP("existing layer", L + "/occ", multipart(MAP.yaml(), MAP.pgm()), 409, "conflict"),
        MP("oversized", L + "/newocc",
           multipart(MAP.yaml(), MAP.pgm(), [("pad", "pad.bin", "application/octet-stream", b"\0" * MAX_BODY)]),
           413, "payload_too_large"),
    ],
    "observations": [
        C("truncated json", "POST", OBS_PATH, obs()[:-5], 400, "invalid_json"),
        C("NaN", "POST", OBS_PATH, obs().replace('"range_m": 2.0', '"range_m": NaN'), 400, "invalid_json"),
        C("Infinity literal", "POST", OBS_PATH, obs().replace('"range_m": 2.0', '"range_m": Infinity'), 400,
          "invalid_json"),
        C("fov wrong type", "POST", OBS_PATH, obs(fov_rad="wide"), 400, "invalid_argument", "fov_rad"),
        C("pose wrong type", "POST", OBS_PATH, obs(pose=[1, 2]), 400, "invalid_argument", "pose"),
        C("position 2d", "POST", OBS_PATH, obs(**{"pose.position": [0.5, 0.5]}), 400, "invalid_argument",
          "pose.position"),
        C("orientation wrong type", "POST", OBS_PATH, obs(**{"pose.orientation": "north"}), 400, "invalid_argument",
          "pose.orientation"),
        C("stimulus wrong type", "POST", OBS_PATH, obs(stimulus="here"), 400, "invalid_argument", "stimulus"),
        C("vertex wrong type", "POST", OBS_PATH, obs(stimulus=[[[0.9, 0.2], [1.2, "x"], [1.2, 0.5]]]), 400,
          "invalid_argument", "stimulus[0][1][1]"),
        C("range missing", "POST", OBS_PATH, obs(range_m=None), 400, "invalid_argument", "range_m"),
        C("unknown key", "POST", OBS_PATH, obs(colour="red"), 400, "invalid_argument", "colour"),
        C("stamp garbage", "POST", OBS_PATH, obs(stamp="yesterday"), 400, "invalid_argument", "stamp"),
        C("range 1e999", "POST", OBS_PATH, obs().replace('"range_m": 2.0', '"range_m": 1e999'), 400,
          "invalid_json", overflow=True),
        C("position -1e999", "POST", OBS_PATH, obs().replace('"position": [0.5,', '"position": [-1e999,'), 400,
          "invalid_json", overflow=True),
        C("vertex 1e999", "POST", OBS_PATH, obs().replace("[0.9, 0.2]", "[1e999, 0.2]"), 400, "invalid_json",
          overflow=True),
        C("quaternion [0,0,0,2]", "POST", OBS_PATH, obs(**{"pose.orientation": [0, 0, 0, 2]}), 422, "unprocessable",
          "pose.orientation"),
        C("quaternion zero", "POST", OBS_PATH, obs(**{"pose.orientation": [0, 0, 0, 0]}), 422, "unprocessable",
          "pose.orientation"),
        C("quaternion norm 1.01", "POST", OBS_PATH, obs(**{"pose.orientation": [0, 0, 0.1, 1.005]}), 422,
          "unprocessable", "pose.orientation"),
        C("fov too wide", "POST", OBS_PATH, obs(fov_rad=7.0), 422, "unprocessable", "fov_rad"),
        C("range negative", "POST", OBS_PATH, obs(range_m=-1.0), 422, "unprocessable", "range_m"),
        C("polygon of 2 vertices", "POST", OBS_PATH, obs(stimulus=[[[0.9, 0.2], [1.2, 0.2]]]), 422, "unprocessable",
          "stimulus[0]"),
        C("sensor outside the grid", "POST", OBS_PATH, obs(**{"pose.position": [50.0, 0.5, 0.0]}), 422,
          "unprocessable", "pose.position"),
        C("unknown map", "POST", "/v1/maps/ghost/layers/prob/observations", obs(), 404, "not_found", "map"),
        C("unknown layer", "POST", L + "/ghost/observations", obs(), 404, "not_found", "layer"),
        C("occupancy layer", "POST", L + "/occ/observations", obs(), 422, "unprocessable", "layer"),
        C("too many polygons", "POST", OBS_PATH, obs(stimulus=[SQUARE] * (MAX_POLYGONS + 1)), 413,
          "payload_too_large", "stimulus"),
        C("too many vertices", "POST", OBS_PATH,
          obs(stimulus=[[[1.0 + 0.01 * k, 0.2 + 0.001 * k * k] for k in range(MAX_VERTICES + 1)]]), 413,
          "payload_too_large", "stimulus[0]"),
        C("oversized", "POST", OBS_PATH, padded(OBS, MAX_BODY + 100), 413, "payload_too_large"),
    ],
    "labels": [
        C("truncated json", "POST", LABEL_PATH, '{"label": "kitchen", "polygons": [', 400, "invalid_json"),
        C("NaN", "POST", LABEL_PATH, '{"label": "kitchen", "polygons": [[[NaN, 0], [1, 0], [1, 1]]]}', 400,
          "invalid_json"),
        C("label wrong type", "POST", LABEL_PATH, json.dumps({"label": 5, "polygons": [SQUARE]}), 400,
          "invalid_argument", "label"),
        C("label empty", "POST", LABEL_PATH, json.dumps({"label": "", "polygons": [SQUARE]}), 400,
          "invalid_argument", "label"),
        C("polygons wrong type", "POST", LABEL_PATH, json.dumps({"label": "k", "polygons": "all"}), 400,
          "invalid_argument", "polygons"),
        C("vertex 1e999", "POST", LABEL_PATH, '{"label": "k", "polygons": [[[1e999, 0], [1, 0], [1, 1]]]}', 400,
          "invalid_json", overflow=True),
        C("too many polygons", "POST", LABEL_PATH, json.dumps({"label": "k", "polygons": [SQUARE] * 5}), 413,
          "payload_too_large", "polygons"),
        C("probability layer", "POST", L + "/prob/labels", json.dumps({"label": "k", "polygons": [SQUARE]}), 422,
          "unprocessable", "layer"),
        C("unknown layer", "POST", L + "/ghost/labels", json.dumps({"label": "k", "polygons": [SQUARE]}), 404,
          "not_found", "layer"),
        C("unknown map", "POST", "/v1/maps/ghost/layers/lab/labels", json.dumps({"label": "k", "polygons": [SQUARE]}),
          404, "not_found", "map"),
        C("oversized", "POST", LABEL_PATH, padded({"label": "k", "polygons": [SQUARE]}, MAX_BODY + 100), 413,
          "payload_too_large"),
    ],
    "regions": [
        C("threshold not a number", "GET", L + "/prob/regions?threshold=abc", None, 400, "invalid_argument",
          "threshold"),
        C("threshold 1e999", "GET", L + "/prob/regions?threshold=1e999", None, 400, "invalid_argument", "threshold"),
        C("threshold nan", "GET", L + "/prob/regions?threshold=nan", None, 400, "invalid_argument", "threshold"),
        C("threshold inf", "GET", L + "/prob/regions?threshold=inf", None, 400, "invalid_argument", "threshold"),
        C("threshold empty", "GET", L + "/prob/regions?threshold=", None, 400, "invalid_argument", "threshold"),
        C("threshold above 1", "GET", L + "/prob/regions?threshold=1.5", None, 422, "unprocessable", "threshold"),
        C("min_area negative", "GET", L + "/prob/regions?min_area_m2=-1", None, 422, "unprocessable", "min_area_m2"),
        C("unknown layer", "GET", L + "/ghost/regions", None, 404, "not_found", "layer"),
        C("unknown map", "GET", "/v1/maps/ghost/layers/prob/regions", None, 404, "not_found", "map"),
    ],
    "agents": [
        C("truncated json", "PUT", AGENT_PATH, '{"position": [1, 2], "heading_rad"', 400, "invalid_json"),
        C("NaN", "PUT", AGENT_PATH, '{"position": [1, 2], "heading_rad": NaN}', 400, "invalid_json"),
        C("position wrong type", "PUT", AGENT_PATH, '{"position": "here", "heading_rad": 0}', 400,
          "invalid_argument", "position"),
        C("position 1d", "PUT", AGENT_PATH, '{"position": [1], "heading_rad": 0}', 400, "invalid_argument",
          "position"),
        C("heading wrong type", "PUT", AGENT_PATH, '{"position": [1, 2], "heading_rad": "north"}', 400,
          "invalid_argument", "heading_rad"),
        C("heading missing", "PUT", AGENT_PATH, '{"position": [1, 2]}', 400, "invalid_argument", "heading_rad"),
        C("stamp negative", "PUT", AGENT_PATH, '{"position": [1, 2], "heading_rad": 0, "stamp": -5}', 400,
          "invalid_argument", "stamp"),
        C("heading 1e999", "PUT", AGENT_PATH, '{"position": [1, 2], "heading_rad": 1e999}', 400, "invalid_json",
          overflow=True),
        C("velocity 1e999", "PUT", AGENT_PATH, '{"position": [1, 2], "heading_rad": 0, "velocity": [1e999, 0]}',
          400, "invalid_json", overflow=True),
        C("unknown map", "PUT", "/v1/maps/ghost/agents/p2", '{"position": [1, 2], "heading_rad": 0}', 404,
          "not_found", "map"),
        C("oversized", "PUT", AGENT_PATH, padded({"position": [1, 2], "heading_rad": 0}, MAX_BODY + 100), 413,
          "payload_too_large"),
        C("unknown agent", "GET", "/v1/maps/m/agents/ghost", None, 404, "not_found", "agent"),
        C("bbox of 3 numbers", "GET", "/v1/maps/m/agents?bbox=1,2,3", None, 400, "invalid_argument", "bbox"),
        C("bbox inf", "GET", "/v1/maps/m/agents?bbox=0,0,inf,1", None, 400, "invalid_argument", "bbox"),
        C("bbox inverted", "GET", "/v1/maps/m/agents?bbox=3,0,1,1", None, 422, "unprocessable", "bbox"),
        C("agents of unknown map", "GET", "/v1/maps/ghost/agents", None, 404, "not_found", "map"),
    ],
    "attention": [
        C("agent missing", "GET", "/v1/maps/m/attention?layer=prob", None, 400, "invalid_argument", "agent"),
        C("layer missing", "GET", "/v1/maps/m/attention?agent=p", None, 400, "invalid_argument", "layer"),
        C("agent id invalid", "GET", "/v1/maps/m/attention?agent=a%20b&layer=prob", None, 400, "invalid_argument",
          "agent"),
        C("threshold not a number", "GET", "/v1/maps/m/attention?agent=p&layer=prob&threshold=x", None, 400,
          "invalid_argument", "threshold"),
        C("threshold 1e999", "GET", "/v1/maps/m/attention?agent=p&layer=prob&threshold=1e999", None, 400,
          "invalid_argument", "threshold"),
        C("threshold negative", "GET", "/v1/maps/m/attention?agent=p&layer=prob&threshold=-0.5", None, 422,
          "unprocessable", "threshold"),
        C("unknown agent", "GET", "/v1/maps/m/attention?agent=ghost&layer=prob", None, 404, "not_found", "agent"),
        C("unknown layer", "GET", "/v1/maps/m/attention?agent=p&layer=ghost", None, 404, "not_found", "layer"),
        C("unknown map", "GET", "/v1/maps/ghost/attention?agent=p&layer=prob", None, 404, "not_found", "map"),
    ],
    "viewpoints": [
        C("truncated json", "POST", VP_PATH, vp()[:-3], 400, "invalid_json"),
        C("NaN", "POST", VP_PATH, vp().replace("[0.5, 0.5]", "[NaN, 0.5]"), 400, "invalid_json"),
        C("robot wrong type", "POST", VP_PATH, vp(robot="dock"), 400, "invalid_argument", "robot"),
        C("agent wrong type", "POST", VP_PATH, vp(agent=5), 400, "invalid_argument", "agent"),
        C("max wrong type", "POST", VP_PATH, vp(max="ten"), 400, "invalid_argument", "max"),
        C("max fractional", "POST", VP_PATH, vp(max=1.5), 400, "invalid_argument", "max"),
        C("unknown key", "POST", VP_PATH, vp(speed=1), 400, "invalid_argument", "speed"),
        C("robot 1e999", "POST", VP_PATH, vp().replace("[0.5, 0.5]", "[1e999, 0.5]"), 400, "invalid_json",
          overflow=True),
        C("threshold 1e999", "POST", VP_PATH, vp().replace("}", ', "threshold": 1e999}'), 400, "invalid_json",
          overflow=True),
        C("max 0", "POST", VP_PATH, vp(max=0), 422, "unprocessable", "max"),
        C("threshold 2", "POST", VP_PATH, vp(threshold=2), 422, "unprocessable", "threshold"),
        C("robot on a wall", "POST", VP_PATH, vp(robot=list(MAP.cell_center(20, 5))), 422, "unprocessable", "robot"),
        C("unknown agent", "POST", VP_PATH, vp(agent="ghost"), 404, "not_found", "agent"),
        C("unknown layer", "POST", VP_PATH, vp(layer="ghost"), 404, "not_found", "layer"),
        C("unknown map", "POST", "/v1/maps/ghost/viewpoints", vp(), 404, "not_found", "map"),
        C("oversized", "POST", VP_PATH, padded(VP, MAX_BODY + 100), 413, "payload_too_large"),
    ],
    "ids_in_the_path": [
        # Ids in the path obey the same rule as ids in bodies: 1-64 characters of [A-Za-z0-9_.-], no leading '.'.
        C("layer name '..'", "PUT", L + "/..", '{"kind": "probability", "base": "occ"}', 400, "invalid_argument",
          "layer"),
        C("layer name '.hidden'", "PUT", L + "/.hidden", '{"kind": "probability", "base": "occ"}', 400,
          "invalid_argument", "layer"),
        C("layer name of 65 characters", "PUT", L + "/" + "x" * 65, '{"kind": "probability", "base": "occ"}', 400,
          "invalid_argument", "layer"),
        MP("occupancy layer name '.occ'", L + "/.occ", multipart(MAP.yaml(), MAP.pgm()), 400,
           "invalid_argument", "layer"),
        C("agent id '.a'", "PUT", "/v1/maps/m/agents/.a", '{"position": [1, 2], "heading_rad": 0}', 400,
          "invalid_argument", "agent"),
        C("agent id of 65 characters", "PUT", "/v1/maps/m/agents/" + "a" * 65,
          '{"position": [1, 2], "heading_rad": 0}', 400, "invalid_argument", "agent"),
    ],
    "read_layer_and_maps": [
        C("format bmp occupancy", "GET", L + "/occ?format=bmp", None, 400, "invalid_argument", "format"),
        C("format bmp probability", "GET", L + "/prob?format=bmp", None, 400, "invalid_argument", "format"),
        C("format bmp label", "GET", L + "/lab?format=bmp", None, 400, "invalid_argument", "format"),
        C("format bmp fused", "GET", L + "/fz?format=bmp", None, 400, "invalid_argument", "format"),
        C("format empty", "GET", L + "/prob?format=", None, 400, "invalid_argument", "format"),
        C("statistics maybe", "GET", L + "/prob?statistics=maybe", None, 400, "invalid_argument", "statistics"),
        C("unknown layer", "GET", L + "/ghost", None, 404, "not_found", "layer"),
        C("unknown layer raw", "GET", L + "/ghost?format=raw", None, 404, "not_found", "layer"),
        C("unknown map layers", "GET", "/v1/maps/ghost/layers", None, 404, "not_found", "map"),
        C("unknown map", "GET", "/v1/maps/ghost", None, 404, "not_found", "map"),
        C("list limit 0", "GET", "/v1/maps?limit=0", None, 422, "unprocessable", "limit"),
        C("list limit text", "GET", "/v1/maps?limit=ten", None, 400, "invalid_argument", "limit"),
        C("list limit fractional", "GET", "/v1/maps?limit=2.5", None, 400, "invalid_argument", "limit"),
        C("delete unknown map", "DELETE", "/v1/maps/ghost", None, 404, "not_found", "map"),
        C("delete unknown layer", "DELETE", L + "/ghost", None, 404, "not_found", "layer"),
        C("delete base of other layers", "DELETE", L + "/occ", None, 409, "conflict", "layer"),
    ],
}
