"""Starts the real anchordb server binary on loopback for integration tests.

    server = Server(self, extra_args=["--max_body_bytes=4096"])   # registers its own cleanup on the TestCase
    c = server.client                                              # an anchordb_client.Client
    server.stop(); server.start()                                  # SIGTERM + wait, then again on the same db file
    server.kill()                                                  # kill -9

The binary is $ANCHORDB_BIN; the server runs `serve --db <tmpdir>/x.sqlite --port 0 [extra flags]` and the
harness learns the port from the first stdout line ("anchordb listening on http://127.0.0.1:PORT ..."). A server
that exits early (or dies under a test) fails the test with its exit status and stderr.
"""

import os
import re
import select
import shutil
import signal
import subprocess
import tempfile
import threading
import time
import urllib.error

import anchordb_client

START_TIMEOUT_S = 20.0
STOP_TIMEOUT_S = 20.0
_LISTENING = re.compile(r"anchordb listening on (http://[^\s:]+:(\d+))")


def binary():
    path = os.environ.get("ANCHORDB_BIN")
    if not path:
        raise RuntimeError("ANCHORDB_BIN is not set: point it at the anchordb server binary "
                           "(e.g. build/server/anchordb)")
    if not os.access(path, os.X_OK):
        raise RuntimeError("ANCHORDB_BIN=%s is not an executable file" % path)
    return path


def shared_data(*parts):
    """A path below $ANCHORDB_SHARED_DATA (default: ../shared/data next to the project)."""
    root = os.environ.get("ANCHORDB_SHARED_DATA") or os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "shared", "data")
    path = os.path.join(root, *parts)
    if not os.path.exists(path):
        raise RuntimeError("shared data file %s is missing (ANCHORDB_SHARED_DATA=%s)" % (path, root))
    return path


def clean_env():
    """The environment without ANCHORDB_* settings (the server reads ANCHORDB_<SETTING> variables)."""
    return {k: v for k, v in os.environ.items() if not k.startswith("ANCHORDB_")}


# ---------------------------------------------------------------- the engine switch
# With ANCHORDB_TEST_ENGINE=postgresql every database file a test names (servers, CLI commands) becomes a database
# of its own on one scratch PostgreSQL 15 per test process (scripts/pg-scratch, stopped when the process exits);
# the same path again gives the same database. Tests that open the SQLite file themselves stay SQLite's.
_PG = {"folder": None, "uri": None, "env": None, "databases": {}}


def _pg_database(path):
    if _PG["uri"] is None:
        import atexit
        parent = tempfile.mkdtemp(prefix="anchordb-pg-")
        os.chmod(parent, 0o755)  # the server runs as 'postgres' when the tests run as root
        folder = os.path.join(parent, "pg")
        script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "pg-scratch")
        out = subprocess.run([script, "start", folder], capture_output=True, text=True, timeout=180)
        if out.returncode != 0:
            raise RuntimeError("scripts/pg-scratch start failed: " + out.stderr)
        atexit.register(lambda: (subprocess.run([script, "stop", folder], capture_output=True, timeout=120),
                                 shutil.rmtree(parent, True)))
        _PG["uri"] = out.stdout.strip().splitlines()[-1]
        with open(os.path.join(folder, "pg.env"), encoding="utf-8") as f:
            _PG["env"] = dict(line.rstrip("\n").split("=", 1) for line in f if "=" in line)
    if path not in _PG["databases"]:
        name = "it_%d_%d" % (os.getpid(), len(_PG["databases"]) + 1)
        env = _PG["env"]
        psql = ["/usr/lib/postgresql/15/bin/psql", "-h", env["PGHOST"], "-p", env["PGPORT"], "-U", "postgres",
                "-d", "postgres", "-qc", "CREATE DATABASE " + name]
        out = subprocess.run((["runuser", "-u", "postgres", "--"] if os.getuid() == 0 else []) + psql,
                             capture_output=True, text=True, timeout=60)
        if out.returncode != 0:
            raise RuntimeError("CREATE DATABASE failed: " + out.stderr)
        _PG["databases"][path] = _PG["uri"].rsplit("/", 1)[0] + "/" + name
    return _PG["databases"][path]


def database_location(path):
    """What a server or CLI command opens for the database file `path` (see the engine switch above)."""
    if os.environ.get("ANCHORDB_TEST_ENGINE") != "postgresql" or path.startswith(("postgresql://", "postgres://")):
        return path
    return _pg_database(path)


def run_cli(args, timeout=30):
    """Runs `$ANCHORDB_BIN args...`; returns CompletedProcess with text stdout/stderr."""
    args = list(args)
    for i in range(len(args) - 1):
        if args[i] == "--db":
            args[i + 1] = database_location(args[i + 1])
    return subprocess.run([binary()] + args, capture_output=True, text=True, timeout=timeout, env=clean_env())


def create_token(db_path, role):
    """`anchordb token create --role ROLE --db FILE`; returns the printed secret."""
    out = run_cli(["token", "create", "--role", role, "--db", db_path])
    if out.returncode != 0:
        raise AssertionError("token create --role %s failed (exit %d): %s" % (role, out.returncode, out.stderr))
    m = re.search(r"\): (\S+)", out.stdout)
    if not m:
        raise AssertionError("token create printed no secret: %r" % out.stdout)
    return m.group(1)


def server_with_tokens(roles=("reader", "writer", "admin"), before_start=None):
    """A server started with --auth=required after `anchordb token create` made one token per role; returns
    (server, {role: secret}). `before_start(db_path)` may change the file first. The caller closes the server."""
    server = Server(None, start=False)
    try:
        secrets = {role: create_token(server.db_path, role) for role in roles}
        if before_start:
            before_start(server.db_path)
        server.extra_args = ["--auth=required"]
        server.start()
    except Exception:
        server.close()
        raise
    return server, secrets


class ServerDied(AssertionError):
    pass


class _Client(anchordb_client.Client):
    """A Client that, when the connection fails, says whether the server process is gone and shows its stderr."""

    def __init__(self, server, base_url, token=None, timeout=30):
        super().__init__(base_url, token=token, timeout=timeout)
        self._server = server

    def request(self, method, path, body=None, headers=None, raw=False):
        try:
            return super().request(method, path, body, headers, raw)
        except (urllib.error.URLError, ConnectionError) as e:
            if self._server.proc is not None and self._server.proc.poll() is not None and not self._server.expect_exit:
                raise ServerDied("%s %s failed (%s): the server exited with status %s\n--- server stderr ---\n%s" % (
                    method, path, e, self._server.proc.returncode, self._server.stderr_text())) from e
            raise


class Server:
    """One anchordb server process over a database file in a temporary directory.

    test: a unittest.TestCase (cleanup is registered on it) or None (call close() yourself).
    db_path: an existing database file to serve; by default <tmpdir>/x.sqlite.
    sqlite_file: serve db_path as the SQLite file it is under either engine switch (a test that brings the file's
    content itself, such as a database of an earlier release).
    """

    def __init__(self, test=None, extra_args=(), db_path=None, start=True, token=None, sqlite_file=False):
        self.tmpdir = tempfile.mkdtemp(prefix="anchordb-it-")
        self.db_path = db_path or os.path.join(self.tmpdir, "x.sqlite")
        self.sqlite_file = sqlite_file
        self.extra_args = list(extra_args)
        self.token = token
        self.proc = None
        self.port = None
        self.base_url = None
        self.client = None
        self.expect_exit = False
        self._stderr_path = None
        self._stderr_file = None
        self._starts = 0
        if test is not None:
            test.addCleanup(self.close)
        if start:
            try:
                self.start()
            except BaseException:
                if test is None:
                    self.close()  # nobody else will remove the temporary directory
                raise

    # ---------------------------------------------------------------- lifecycle

    def start(self, extra_args=None):
        """Starts the server (again) on the same database file; returns the client."""
        if self.proc is not None and self.proc.poll() is None:
            raise RuntimeError("the server is already running")
        if extra_args is not None:
            self.extra_args = list(extra_args)
        self._starts += 1
        self._stderr_path = os.path.join(self.tmpdir, "stderr.%d.txt" % self._starts)
        self._stderr_file = open(self._stderr_path, "wb")
        location = self.db_path if self.sqlite_file else database_location(self.db_path)
        args = [binary(), "serve", "--db", location, "--port", "0"] + self.extra_args
        self.expect_exit = False
        self.proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=self._stderr_file, env=clean_env(),
                                     cwd=self.tmpdir)
        line = self._read_first_line(START_TIMEOUT_S)
        m = _LISTENING.search(line)
        if not m:
            self._abort()
            raise ServerDied("server did not announce its port (command %s)\nfirst stdout line: %r\n"
                             "exit status: %s\n--- server stderr ---\n%s" % (
                                 " ".join(args), line, self.proc.returncode, self.stderr_text()))
        self.base_url = m.group(1)
        self.port = int(m.group(2))
        # Keep draining stdout so the server never blocks on a full pipe.
        threading.Thread(target=self._drain, args=(self.proc.stdout,), daemon=True).start()
        self.client = self.make_client(self.token)
        return self.client

    def make_client(self, token=None, timeout=30):
        return _Client(self, self.base_url, token=token, timeout=timeout)

    def _read_first_line(self, timeout):
        fd = self.proc.stdout.fileno()
        deadline = time.monotonic() + timeout
        buf = b""
        while b"\n" not in buf:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                break
            ready, _, _ = select.select([fd], [], [], remaining)
            if not ready:
                break
            chunk = os.read(fd, 4096)
            if not chunk:  # EOF: the process exited (or closed stdout)
                break
            buf += chunk
        if b"\n" not in buf:
            # Give an exiting process a moment so its status and stderr are complete.
            try:
                self.proc.wait(timeout=2)
            except subprocess.TimeoutExpired:
                pass
        return buf.split(b"\n", 1)[0].decode("utf-8", "replace")

    @staticmethod
    def _drain(stream):
        try:
            while stream.read(4096):
                pass
        except (OSError, ValueError):
            pass

    def stderr_text(self):
        if self._stderr_file is not None:
            self._stderr_file.flush()
        try:
            with open(self._stderr_path, "rb") as f:
                return f.read().decode("utf-8", "replace")[-8000:]
        except (OSError, TypeError):
            return ""

    def alive(self):
        return self.proc is not None and self.proc.poll() is None

    def check_alive(self):
        """Fails (ServerDied) if the server exited on its own."""
        if self.proc is not None and self.proc.poll() is not None:
            raise ServerDied("the server exited with status %s\n--- server stderr ---\n%s" % (
                self.proc.returncode, self.stderr_text()))

    def stop(self, timeout=STOP_TIMEOUT_S):
        """SIGTERM and wait; returns the exit status. Fails if the server had already died on its own."""
        self.check_alive()
        self.expect_exit = True
        self.proc.send_signal(signal.SIGTERM)
        try:
            code = self.proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
            raise ServerDied("the server did not stop within %.0f s of SIGTERM\n--- server stderr ---\n%s" % (
                timeout, self.stderr_text()))
        self._close_pipes()
        return code

    def kill(self):
        """kill -9 and wait (the server gets no chance to clean up)."""
        self.check_alive()
        self.expect_exit = True
        self.proc.send_signal(signal.SIGKILL)
        self.proc.wait()
        self._close_pipes()

    def restart(self, extra_args=None):
        if self.alive():
            self.stop()
        return self.start(extra_args)

    def _abort(self):
        if self.proc is not None and self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()
        self._close_pipes()

    def _close_pipes(self):
        if self.proc is not None and self.proc.stdout is not None:
            try:
                self.proc.stdout.close()
            except OSError:
                pass
        if self._stderr_file is not None:
            self._stderr_file.close()
            self._stderr_file = None

    def close(self):
        """Stops a running server (kill if SIGTERM does not work) and removes the temporary directory."""
        try:
            if self.proc is not None and self.proc.poll() is None:
                self.expect_exit = True
                self.proc.send_signal(signal.SIGTERM)
                try:
                    self.proc.wait(timeout=STOP_TIMEOUT_S)
                except subprocess.TimeoutExpired:
                    self.proc.kill()
                    self.proc.wait()
            self._close_pipes()
        finally:
            shutil.rmtree(self.tmpdir, ignore_errors=True)


def run_server_expecting_exit(args, timeout=20):
    """Runs `$ANCHORDB_BIN serve args...` that is expected to refuse to start; returns CompletedProcess.

    Fails if the server is still running after `timeout` seconds (it is killed first)."""
    try:
        return subprocess.run([binary(), "serve"] + list(args), capture_output=True, text=True, timeout=timeout,
                              env=clean_env())
    except subprocess.TimeoutExpired as e:
        raise AssertionError("the server kept running although it should have refused to start: %s\nstdout: %s" % (
            " ".join(args), e.stdout)) from e


def pg_scratch(test):
    """A throwaway PostgreSQL 15 for `test` (scripts/pg-scratch in a temporary folder, stopped and removed by the
    test's cleanup); returns (folder, URI of its empty database 'anchordb', the variables of its pg.env)."""
    parent = tempfile.mkdtemp(prefix="anchordb-pg-")
    os.chmod(parent, 0o755)  # the server runs as 'postgres' when the tests run as root
    test.addCleanup(shutil.rmtree, parent, True)
    folder = os.path.join(parent, "pg")
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "pg-scratch")
    out = subprocess.run([script, "start", folder], capture_output=True, text=True, timeout=180)
    test.assertEqual(out.returncode, 0, out.stderr)
    test.addCleanup(subprocess.run, [script, "stop", folder], capture_output=True, timeout=120)
    with open(os.path.join(folder, "pg.env"), encoding="utf-8") as f:
        env = dict(line.rstrip("\n").split("=", 1) for line in f if "=" in line)
    return folder, out.stdout.strip().splitlines()[-1], env


# ---------------------------------------------------------------- small helpers shared by the tests

def soundness(db_path):
    """(PRAGMA integrity_check text, PRAGMA foreign_key_check rows) of a database file; ("ok", []) when sound."""
    import sqlite3
    con = sqlite3.connect(db_path, timeout=30)
    try:
        return ("; ".join(r[0] for r in con.execute("PRAGMA integrity_check")),
                con.execute("PRAGMA foreign_key_check").fetchall())
    finally:
        con.close()


def identity_pose(x, y, yaw=0.0):
    """A pose at (x, y, 0) whose x axis has heading `yaw` in the map frame."""
    import math
    return {"position": [x, y, 0.0], "orientation": [0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0)]}


def parse_pgm(data):
    """(width, height, maxval, pixel bytes) of a binary (P5) PGM."""
    if data[:2] != b"P5":
        raise ValueError("not a P5 PGM")
    pos = 2
    values = []
    while len(values) < 3:
        while data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            while data[pos:pos + 1] not in (b"\n", b""):
                pos += 1
            continue
        start = pos
        while pos < len(data) and data[pos:pos + 1].isdigit():
            pos += 1
        values.append(int(data[start:pos]))
    pos += 1  # one whitespace byte after maxval
    w, h, maxval = values
    return w, h, maxval, data[pos:pos + w * h]


def parse_map_yaml(text):
    """The key/values of a map_server YAML as Python values: numbers as floats, lists of numbers, strings."""
    if isinstance(text, bytes):
        text = text.decode("utf-8")
    out = {}
    for line in text.splitlines():
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        key, _, value = line.partition(":")
        value = value.strip()
        if value.startswith("[") and value.endswith("]"):
            out[key.strip()] = [float(v) for v in value[1:-1].split(",")]
        else:
            try:
                out[key.strip()] = float(value)
            except ValueError:
                out[key.strip()] = value.strip("'\"")
    return out


def encode_png_grey(width, height, pixels):
    """A minimal 8-bit greyscale PNG (no filtering) of `pixels` in image order."""
    import struct
    import zlib

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff)

    rows = b"".join(b"\x00" + bytes(pixels[r * width:(r + 1) * width]) for r in range(height))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b""))


def decode_png_grey(data):
    """(width, height, pixel bytes) of an 8-bit greyscale, non-interlaced PNG (any filter types)."""
    width, height, depth, pixels = decode_png_grey_any(data)
    if depth != 8:
        raise ValueError("only 8-bit grey non-interlaced PNGs are decoded here (got depth %d colour 0)" % depth)
    return width, height, pixels


def decode_png_grey_any(data):
    """(width, height, bit depth, unfiltered pixel bytes, big-endian for 16 bit) of a non-interlaced greyscale PNG
    of 8 or 16 bits (any filter types)."""
    import struct
    import zlib
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("not a PNG")
    pos, idat, ihdr = 8, b"", None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        kind = data[pos + 4:pos + 8]
        body = data[pos + 8:pos + 8 + length]
        pos += 12 + length
        if kind == b"IHDR":
            ihdr = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        elif kind == b"IEND":
            break
    width, height, depth, colour, _, _, interlace = ihdr
    if depth not in (8, 16) or colour != 0 or interlace != 0:
        raise ValueError("only 8/16-bit grey non-interlaced PNGs are decoded here (got depth %d colour %d)" % (
            depth, colour))
    bpp = depth // 8
    stride = width * bpp
    raw = zlib.decompress(idat)
    out = bytearray()
    prev = bytearray(stride)
    for r in range(height):
        ftype = raw[r * (stride + 1)]
        line = bytearray(raw[r * (stride + 1) + 1:(r + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            if ftype == 1:
                line[i] = (line[i] + a) & 255
            elif ftype == 2:
                line[i] = (line[i] + b) & 255
            elif ftype == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif ftype == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[i] = (line[i] + pred) & 255
        out += line
        prev = line
    return width, height, depth, bytes(out)


FREE, OCCUPIED, UNKNOWN = 254, 0, 205


class SyntheticMap:
    """A map_server map built in Python: `width` x `height` cells, cell (ix, iy) with iy = 0 at the BOTTOM.

    walls / unknown: rectangles (ix0, iy0, ix1, iy1), inclusive, in cell coordinates. Everything else is free.
    """

    def __init__(self, width, height, resolution=0.1, origin=(0.0, 0.0, 0.0), walls=(), unknown=(),
                 border=True, negate=0, occupied_thresh=0.65, free_thresh=0.196, mode=None):
        self.width, self.height = width, height
        self.resolution = resolution
        self.origin = tuple(origin)
        self.negate, self.occupied_thresh, self.free_thresh, self.mode = negate, occupied_thresh, free_thresh, mode
        self.cells = [FREE] * (width * height)  # cell order (iy * width + ix)
        for (x0, y0, x1, y1) in unknown:
            self.fill(x0, y0, x1, y1, UNKNOWN)
        if border:
            self.fill(0, 0, width - 1, 0, OCCUPIED)
            self.fill(0, height - 1, width - 1, height - 1, OCCUPIED)
            self.fill(0, 0, 0, height - 1, OCCUPIED)
            self.fill(width - 1, 0, width - 1, height - 1, OCCUPIED)
        for (x0, y0, x1, y1) in walls:
            self.fill(x0, y0, x1, y1, OCCUPIED)

    def fill(self, x0, y0, x1, y1, value):
        for iy in range(max(0, y0), min(self.height - 1, y1) + 1):
            for ix in range(max(0, x0), min(self.width - 1, x1) + 1):
                self.cells[iy * self.width + ix] = value

    def at(self, ix, iy):
        return self.cells[iy * self.width + ix]

    def cell_center(self, ix, iy):
        """Map-frame centre of a cell (origin yaw 0 only)."""
        return (self.origin[0] + (ix + 0.5) * self.resolution, self.origin[1] + (iy + 0.5) * self.resolution)

    def cell_of(self, x, y):
        import math
        return (int(math.floor((x - self.origin[0]) / self.resolution)),
                int(math.floor((y - self.origin[1]) / self.resolution)))

    @property
    def image_pixels(self):
        """Pixels in image order (row 0 = top of the map = iy height-1)."""
        out = bytearray()
        for row in range(self.height):
            iy = self.height - 1 - row
            out += bytes(self.cells[iy * self.width:(iy + 1) * self.width])
        return bytes(out)

    def pgm(self, comment=True):
        header = b"P5\n" + (b"# CREATOR: anchordb integration test\n" if comment else b"")
        return header + b"%d %d\n255\n" % (self.width, self.height) + self.image_pixels

    def png(self):
        return encode_png_grey(self.width, self.height, self.image_pixels)

    def yaml(self, image="map.pgm"):
        lines = ["image: %s" % image]
        if self.mode:
            lines.append("mode: %s" % self.mode)
        lines += ["resolution: %r" % self.resolution,
                  "origin: [%r, %r, %r]" % self.origin,
                  "negate: %d" % self.negate,
                  "occupied_thresh: %r" % self.occupied_thresh,
                  "free_thresh: %r" % self.free_thresh]
        return ("\n".join(lines) + "\n").encode()
