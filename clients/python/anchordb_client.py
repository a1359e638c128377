"""Python client for the anchordb HTTP/JSON API (standard library only).

One method per route of api/routes.cc; every error response becomes an ApiError that carries the HTTP status
and the fields of the JSON error body {"error": {"code", "message", "field"}}.

    from anchordb_client import Client, ApiError
    c = Client("http://127.0.0.1:8765")
    c.create_map("home", "Our flat")
    c.import_occupancy("home", "occupancy", open("map.yaml", "rb").read(), open("map.pgm", "rb").read())

Units are SI (metres, radians); poses are {"position": [x, y, z], "orientation": [qx, qy, qz, qw]} in the map
frame (ROS order). Layers read with format=raw are bytes in cell order (row iy = 0 is the BOTTOM of the map):
float32 log-odds for probability layers, uint16 labels for label layers, uint8 masks for fused layers; occupancy
layers give the uint8 image pixels in image order (row 0 is the top). The headers of the last response of the
calling thread (X-Grid-Width, X-Grid-Height, X-Layer-Version, X-Request-Id, ...) are in `client.last_headers`.
"""

import json
import threading
import urllib.error
import urllib.parse
import urllib.request
import uuid

__all__ = ["Client", "ApiError", "Response"]


class ApiError(Exception):
    """An HTTP error response of the server.

    status: HTTP status (int); code, message, field: from the JSON error body (None when absent or when the body
    is not the documented JSON error); body: raw response bytes; headers: dict of response headers (lower-case keys).
    """

    def __init__(self, status, code, message, field=None, body=b"", headers=None):
        self.status = status
        self.code = code
        self.message = message
        self.field = field
        self.body = body
        self.headers = headers or {}
        super().__init__("HTTP %s %s: %s%s" % (status, code, message, " (field %s)" % field if field else ""))


class Response:
    """A raw response: status (int), headers (dict, lower-case keys), body (bytes)."""

    def __init__(self, status, headers, body):
        self.status = status
        self.headers = headers
        self.body = body

    def json(self):
        return json.loads(self.body.decode("utf-8"))

    def __repr__(self):
        return "Response(status=%d, %d bytes)" % (self.status, len(self.body))


def _quote(segment):
    return urllib.parse.quote(str(segment), safe="")


def _query(params):
    items = [(k, v) for k, v in params.items() if v is not None]
    if not items:
        return ""
    out = []
    for k, v in items:
        if isinstance(v, bool):
            v = "true" if v else "false"
        elif isinstance(v, (list, tuple)):
            v = ",".join(repr(float(x)) if isinstance(x, float) else str(x) for x in v)
        out.append((k, str(v)))
    return "?" + urllib.parse.urlencode(out)


def _multipart(parts):
    """parts: list of (name, filename, content_type, bytes). Returns (body bytes, content-type header)."""
    boundary = "anchordb-" + uuid.uuid4().hex
    chunks = []
    for name, filename, content_type, data in parts:
        if isinstance(data, str):
            data = data.encode("utf-8")
        chunks.append(("--%s\r\n" % boundary).encode())
        chunks.append(('Content-Disposition: form-data; name="%s"; filename="%s"\r\n' % (name, filename)).encode())
        chunks.append(("Content-Type: %s\r\n\r\n" % content_type).encode())
        chunks.append(bytes(data))
        chunks.append(b"\r\n")
    chunks.append(("--%s--\r\n" % boundary).encode())
    return b"".join(chunks), "multipart/form-data; boundary=%s" % boundary


class _NoRedirect(urllib.request.HTTPRedirectHandler):
    def redirect_request(self, *args, **kwargs):  # the API never redirects; surface it as an error instead
        return None


class Client:
    """A client of one anchordb server.

    base_url: e.g. "http://127.0.0.1:8765"; token: API token sent as "Authorization: Bearer <token>";
    timeout: seconds per request.
    """

    def __init__(self, base_url, token=None, timeout=30):
        self.base_url = base_url.rstrip("/")
        self.token = token
        self.timeout = timeout
        self._local = threading.local()
        self._opener = urllib.request.build_opener(_NoRedirect())

    # ------------------------------------------------------------------ low level

    @property
    def last_headers(self):
        """Headers (lower-case keys) of the last response this thread received, or {}."""
        return getattr(self._local, "headers", {})

    def request(self, method, path, body=None, headers=None, raw=False):
        """Sends one request; `path` starts with "/" and may carry a query string.

        body: dict or list -> JSON; bytes or str -> sent as is (set Content-Type in `headers`); None -> no body.
        Returns the decoded JSON (or bytes when the response is not JSON); with raw=True a Response whatever
        the status (no ApiError is raised then). Error statuses raise ApiError otherwise.
        """
        hdrs = {"Accept": "application/json"}
        data = None
        if body is not None:
            if isinstance(body, (dict, list)):
                data = json.dumps(body, allow_nan=True).encode("utf-8")
                hdrs["Content-Type"] = "application/json"
            elif isinstance(body, str):
                data = body.encode("utf-8")
                hdrs["Content-Type"] = "application/json"
            else:
                data = bytes(body)
                hdrs["Content-Type"] = "application/octet-stream"
        if self.token:
            hdrs["Authorization"] = "Bearer " + self.token
        if headers:
            hdrs.update(headers)
        req = urllib.request.Request(self.base_url + path, data=data, headers=hdrs, method=method)
        try:
            with self._opener.open(req, timeout=self.timeout) as resp:
                status = resp.status
                resp_headers = {k.lower(): v for k, v in resp.headers.items()}
                payload = resp.read()
        except urllib.error.HTTPError as e:
            status = e.code
            resp_headers = {k.lower(): v for k, v in e.headers.items()} if e.headers else {}
            try:
                payload = e.read()
            except Exception:  # the server may have closed the connection early
                payload = b""
            finally:
                e.close()
        self._local.headers = resp_headers
        if raw:
            return Response(status, resp_headers, payload)
        if status >= 400:
            raise self._error(status, resp_headers, payload)
        if resp_headers.get("content-type", "").startswith("application/json"):
            return json.loads(payload.decode("utf-8")) if payload else None
        return payload

    @staticmethod
    def _error(status, headers, payload):
        code = message = field = None
        try:
            err = json.loads(payload.decode("utf-8"))["error"]
            code, message, field = err.get("code"), err.get("message"), err.get("field")
        except (ValueError, KeyError, TypeError, AttributeError, UnicodeDecodeError):
            message = payload.decode("utf-8", "replace")[:500]
        return ApiError(status, code, message, field, payload, headers)

    # ------------------------------------------------------------------ service

    def health(self):
        return self.request("GET", "/v1/health")

    def settings(self):
        """{"settings": [{"name", "type", "description", "value"}, ...]}"""
        return self.request("GET", "/v1/settings")

    def metrics_text(self):
        """The Prometheus text exposition of GET /metrics."""
        return self.request("GET", "/metrics").decode("utf-8")

    def openapi(self):
        return self.request("GET", "/v1/openapi.json")

    # ------------------------------------------------------------------ maps

    def create_map(self, map_id, name=None):
        body = {"id": map_id}
        if name is not None:
            body["name"] = name
        return self.request("POST", "/v1/maps", body)

    def list_maps(self, limit=None, cursor=None):
        return self.request("GET", "/v1/maps" + _query({"limit": limit, "cursor": cursor}))

    def get_map(self, map_id):
        return self.request("GET", "/v1/maps/%s" % _quote(map_id))

    def delete_map(self, map_id):
        return self.request("DELETE", "/v1/maps/%s" % _quote(map_id))

    # ------------------------------------------------------------------ layers

    def _layer_path(self, map_id, layer):
        return "/v1/maps/%s/layers/%s" % (_quote(map_id), _quote(layer))

    def list_layers(self, map_id):
        return self.request("GET", "/v1/maps/%s/layers" % _quote(map_id))

    def import_occupancy(self, map_id, layer, yaml_bytes, image_bytes):
        """Imports a ROS map_server map: the YAML text and the PGM or PNG image (bytes)."""
        image_bytes = bytes(image_bytes)
        is_png = image_bytes[:8] == b"\x89PNG\r\n\x1a\n"
        body, content_type = _multipart([
            ("yaml", layer + ".yaml", "application/yaml", yaml_bytes),
            ("image", layer + (".png" if is_png else ".pgm"), "image/png" if is_png else "image/x-portable-graymap",
             image_bytes),
        ])
        return self.request("PUT", self._layer_path(map_id, layer), body, {"Content-Type": content_type})

    def create_layer(self, map_id, layer, body):
        """body: {"kind": "probability", "base": ...} | {"kind": "fused", "op": ..., "operands": [...]} |
        {"kind": "label", "base": ..., "labels": {...}}"""
        return self.request("PUT", self._layer_path(map_id, layer), body)

    def get_layer(self, map_id, layer, format="json", statistics=False):  # noqa: A002 (the API's name)
        """format json -> dict; png, pgm, yaml, raw -> bytes (see last_headers for X-Grid-Width/Height)."""
        params = {"format": format}
        if format == "json" and statistics:
            params["statistics"] = True
        return self.request("GET", self._layer_path(map_id, layer) + _query(params))

    def delete_layer(self, map_id, layer):
        return self.request("DELETE", self._layer_path(map_id, layer))

    def observe(self, map_id, layer, pose, fov_rad, range_m, stimulus, stamp=None):
        """pose {"position":[x,y,z],"orientation":[qx,qy,qz,qw]}; stimulus: list of polygons [[x, y], ...]."""
        body = {"pose": pose, "fov_rad": fov_rad, "range_m": range_m, "stimulus": stimulus}
        if stamp is not None:
            body["stamp"] = stamp
        return self.request("POST", self._layer_path(map_id, layer) + "/observations", body)

    def paint_label(self, map_id, layer, label, polygons):
        return self.request("POST", self._layer_path(map_id, layer) + "/labels",
                            {"label": label, "polygons": polygons})

    def regions(self, map_id, layer, threshold=None, min_area_m2=None):
        return self.request("GET", self._layer_path(map_id, layer) + "/regions" +
                            _query({"threshold": threshold, "min_area_m2": min_area_m2}))

    # ------------------------------------------------------------------ agents, attention, viewpoints

    def put_agent(self, map_id, agent, position, heading_rad, velocity=None, stamp=None):
        body = {"position": list(position), "heading_rad": heading_rad}
        if velocity is not None:
            body["velocity"] = list(velocity)
        if stamp is not None:
            body["stamp"] = stamp
        return self.request("PUT", "/v1/maps/%s/agents/%s" % (_quote(map_id), _quote(agent)), body)

    def get_agent(self, map_id, agent):
        return self.request("GET", "/v1/maps/%s/agents/%s" % (_quote(map_id), _quote(agent)))

    def list_agents(self, map_id, bbox=None):
        """bbox: (min_x, min_y, max_x, max_y) in metres."""
        return self.request("GET", "/v1/maps/%s/agents" % _quote(map_id) + _query({"bbox": bbox}))

    def attention(self, map_id, agent, layer, threshold=None):
        return self.request("GET", "/v1/maps/%s/attention" % _quote(map_id) +
                            _query({"agent": agent, "layer": layer, "threshold": threshold}))

    def viewpoints(self, map_id, robot, agent, layer, **opts):
        """opts: threshold, region, max (see the OpenAPI description)."""
        body = {"robot": list(robot), "agent": agent, "layer": layer}
        body.update(opts)
        return self.request("POST", "/v1/maps/%s/viewpoints" % _quote(map_id), body)

    # ------------------------------------------------------------------ events, instances, where-is, forgetting

    def events(self, map_id, since=None, until=None, type=None, instance=None, after=None, limit=None):  # noqa: A002
        return self.request("GET", "/v1/maps/%s/events" % _quote(map_id) +
                            _query({"since": since, "until": until, "type": type, "instance": instance,
                                    "after": after, "limit": limit}))

    def label_event(self, map_id, event_id, label, source="dialog"):
        return self.request("POST", "/v1/maps/%s/events/%d:label" % (_quote(map_id), event_id),
                            {"label": label, "source": source})

    def delete_event(self, map_id, event_id):
        """An operator removes a wrong event (admin; audited); returns the event as it was."""
        return self.request("DELETE", "/v1/maps/%s/events/%d" % (_quote(map_id), event_id))

    def instances(self, map_id, label=None, kind=None, status=None):
        return self.request("GET", "/v1/maps/%s/instances" % _quote(map_id) +
                            _query({"label": label, "kind": kind, "status": status}))

    def create_instance(self, map_id, label, position, kind="furniture", extent=None, yaw_rad=None):
        body = {"kind": kind, "label": label, "position": list(position)}
        if extent is not None:
            body["extent"] = list(extent)
        if yaw_rad is not None:
            body["yaw_rad"] = yaw_rad
        return self.request("POST", "/v1/maps/%s/instances" % _quote(map_id), body)

    def label_instance(self, map_id, instance_id, label, source="dialog"):
        return self.request("POST", "/v1/maps/%s/instances/%d:label" % (_quote(map_id), instance_id),
                            {"label": label, "source": source})

    def history(self, map_id, instance_id):
        return self.request("GET", "/v1/maps/%s/instances/%d/history" % (_quote(map_id), instance_id))

    def where(self, map_id, label, at=None):
        """Where the thing labelled `label` is (or was at time `at`): position, evidence, sentence."""
        return self.request("GET", "/v1/maps/%s/where" % _quote(map_id) + _query({"label": label, "at": at}))

    def forget(self, map_id, policy=None, dry_run=False, now=None):
        """Starts a forgetting job (admin token); returns the job. Poll it with job()."""
        body = {"dry_run": dry_run}
        if policy is not None:
            body["policy"] = policy
        if now is not None:
            body["now"] = now
        return self.request("POST", "/v1/maps/%s:forget" % _quote(map_id), body)

    def job(self, job_id):
        return self.request("GET", "/v1/jobs/%d" % job_id)
