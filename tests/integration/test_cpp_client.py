"""The C++ client (clients/cpp) as a robot component uses it: the library built and installed to a temporary prefix,
its two examples built against the *installed* package (find_package(anchordb_client)), then run against the real
server with tokens: the perception loop posts depth frames from its uint16 buffer and gets a change event, the dialog
component labels the object, asks where it is (the sentence the API gives), meets the typed error of an unknown
label, and waits for a forgetting dry run with progress."""

import os
import re
import shutil
import subprocess
import tempfile
import unittest

import harness

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")


def run(args, cwd=None, timeout=600):
    out = subprocess.run(args, cwd=cwd, capture_output=True, text=True, timeout=timeout)
    if out.returncode != 0:
        raise AssertionError("%s failed (%d):\n%s\n%s" % (" ".join(args), out.returncode, out.stdout[-3000:], out.stderr[-3000:]))
    return out.stdout


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


if __name__ == "__main__":
    unittest.main()
