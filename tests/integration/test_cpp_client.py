"""The C++ client (clients/cpp) as a robot component uses it: the library built and installed to a temporary prefix,
its two examples built against the *installed* package (find_package(anchordb_client)), then run against the real
server with tokens: the perception loop posts depth frames from its uint16 buffer and gets a change event, the dialog
component labels the object, asks where it is (the sentence the API gives), meets the typed error of an unknown
label, and waits for a forgetting dry run with progress. And acceptance 5 of issue 18: the examples, with no --port
or --token, against the server started with the very arguments of ./scripts/run (127.0.0.1:8765, auth auto)."""

import os
import re
import select
import shlex
import shutil
import socket
import subprocess
import tempfile
import threading
import unittest

import harness

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")


def run(args, cwd=None, timeout=600):
    out = subprocess.run(args, cwd=cwd, capture_output=True, text=True, timeout=timeout)
    if out.returncode != 0:
        raise AssertionError("%s failed (%d):\n%s\n%s" % (" ".join(args), out.returncode, out.stdout[-3000:], out.stderr[-3000:]))
    return out.stdout


def scripts_run_serve_args():
    """The arguments ./scripts/run gives `anchordb serve` (its exec line, without the caller's "$@")."""
    with open(os.path.join(ROOT, "scripts", "run")) as f:
        m = re.search(r'^exec \S*/anchordb serve (.*?) "\$@"\s*$', f.read(), re.M)
    if not m:
        raise AssertionError("scripts/run has no `exec .../anchordb serve ... \"$@\"` line")
    return shlex.split(m.group(1))


def port_is_free(host, port):
    with socket.socket() as s:
        try:
            s.bind((host, port))
            return True
        except OSError:
            return False


class CppClientTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="anchordb-cpp-client-")
        prefix = os.path.join(cls.tmp, "prefix")
        generator = ["-G", "Ninja"] if shutil.which("ninja") else []
        launcher = ["-DCMAKE_CXX_COMPILER_LAUNCHER=ccache"] if shutil.which("ccache") else []
        lib_build = os.path.join(cls.tmp, "lib")
        run(["cmake", "-S", os.path.join(ROOT, "clients", "cpp"), "-B", lib_build, "-DCMAKE_BUILD_TYPE=Release",
             "-DCMAKE_INSTALL_PREFIX=" + prefix] + generator + launcher)
        run(["cmake", "--build", lib_build, "-j", "2"])
        run(["cmake", "--install", lib_build])
        cls.prefix = prefix
        examples = os.path.join(cls.tmp, "examples")
        # Only the install prefix: the examples see the package as a robot component's build would.
        run(["cmake", "-S", os.path.join(ROOT, "clients", "cpp", "examples"), "-B", examples,
             "-DCMAKE_BUILD_TYPE=Release", "-DCMAKE_PREFIX_PATH=" + prefix] + generator + launcher)
        run(["cmake", "--build", examples, "-j", "2"])
        cls.examples = examples

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_installed_package_layout(self):
        config = [os.path.join(d, f) for d, _, files in os.walk(self.prefix) for f in files]
        names = {os.path.basename(p) for p in config}
        for wanted in ("anchordb_clientConfig.cmake", "anchordb_clientConfigVersion.cmake", "anchordb_clientTargets.cmake",
                       "client.h", "libanchordb_client.a"):
            self.assertIn(wanted, names)

    def test_examples_run_against_the_server(self):
        server, tokens = harness.server_with_tokens(("reader", "writer", "admin"))
        self.addCleanup(server.close)
        port = str(server.port)
        loop = run([os.path.join(self.examples, "perception_loop"), "--port", port, "--token", tokens["writer"],
                    "--map", "robot", "--frames", "40"], timeout=300)
        self.assertIn("scene 1 opened", loop)
        admin = server.make_client(tokens["admin"])
        events = admin.events("robot")["events"]
        self.assertTrue(any(e["type"] == "added" for e in events), loop)
        self.assertIn("%d events" % len(events), loop)
        # A reader token may not post frames: the typed error names the server's code.
        refused = subprocess.run([os.path.join(self.examples, "perception_loop"), "--port", port, "--token",
                                  tokens["reader"], "--map", "robot2"], capture_output=True, text=True, timeout=120)
        self.assertEqual(refused.returncode, 2)
        self.assertIn("403 forbidden", refused.stderr)
        dialog = run([os.path.join(self.examples, "dialog_where"), "--port", port, "--token", tokens["admin"],
                      "--map", "robot", "--label", "keys", "--forget-dry-run", "1"], timeout=300)
        where = admin.where("robot", "keys")
        self.assertIn("where: " + where["sentence"], dialog)
        self.assertIn("unknown label: 404 not_found (field label)", dialog)
        job = re.search(r"forget dry run: succeeded", dialog)
        self.assertIsNotNone(job, dialog)
        self.assertRegex(dialog, r"job \d+ succeeded \S* 100%")

    def test_examples_with_their_defaults_against_the_server_as_scripts_run_starts_it(self):
        args = scripts_run_serve_args()
        self.assertEqual(args[args.index("--bind") + 1], "127.0.0.1")
        port = int(args[args.index("--port") + 1])
        self.assertEqual(port, 8765)
        extra = []  # the examples' own defaults: 127.0.0.1:8765, no token (auth auto: open on loopback)
        if not port_is_free("127.0.0.1", port):  # another server (a developer's ./scripts/run) holds it
            args[args.index("--port") + 1] = "0"
            extra = None
        home = tempfile.mkdtemp(prefix="anchordb-scripts-run-", dir=self.tmp)
        os.makedirs(os.path.join(home, "var"))  # scripts/run's mkdir -p var; --db ./var/anchordb.sqlite from here
        with open(os.path.join(home, "stderr.txt"), "wb") as err:
            proc = subprocess.Popen([harness.binary(), "serve"] + args, cwd=home, stdout=subprocess.PIPE, stderr=err,
                                    env=harness.clean_env())
        self.addCleanup(lambda: (proc.poll() is None and proc.terminate(), proc.wait(timeout=20)))
        ready, _, _ = select.select([proc.stdout], [], [], harness.START_TIMEOUT_S)
        line = proc.stdout.readline().decode() if ready else ""
        m = re.search(r"anchordb listening on http://127\.0\.0\.1:(\d+)", line)
        self.assertIsNotNone(m, "server started as scripts/run does printed %r" % line)
        threading.Thread(target=harness.Server._drain, args=(proc.stdout,), daemon=True).start()
        if extra is None:
            extra = ["--port", m.group(1)]
        print("server: anchordb serve %s (listening on %s)" % (" ".join(args), m.group(1)))
        loop = run([os.path.join(self.examples, "perception_loop")] + extra, timeout=300)
        print(loop)
        self.assertIn("scene 1 opened", loop)
        self.assertRegex(loop, r"[1-9]\d* events")
        dialog = run([os.path.join(self.examples, "dialog_where")] + extra + ["--label", "keys"], timeout=300)
        print(dialog)
        self.assertIn("where: ", dialog)
        self.assertIn("unknown label: 404 not_found (field label)", dialog)
        self.assertTrue(os.path.getsize(os.path.join(home, "var", "anchordb.sqlite")) > 0)
        proc.terminate()
        self.assertEqual(proc.wait(timeout=20), 0)
        proc.stdout.close()


if __name__ == "__main__":
    unittest.main()
