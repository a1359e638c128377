"""The Python client is an installable package: `pip install clients/python` (pyproject.toml) installs the module
anchordb_client, which then talks to the real server from outside this source tree."""

import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import harness

SOURCE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "clients", "python")


def builder_python():
    """An interpreter whose setuptools can build a wheel offline (pip install --no-build-isolation): this one if it
    has the `wheel` module, else Debian's (python3-setuptools and python3-wheel)."""
    for candidate in (sys.executable, "/usr/bin/python3"):
        if candidate and os.path.exists(candidate) and subprocess.run(
                [candidate, "-c", "import setuptools, wheel"], capture_output=True).returncode == 0:
            return candidate
    raise AssertionError("no Python with setuptools and wheel to run `pip install clients/python` offline")


class PythonPackageTest(unittest.TestCase):
    def test_pip_install_then_use_against_the_server(self):
        tmp = tempfile.mkdtemp(prefix="anchordb-pip-")
        self.addCleanup(shutil.rmtree, tmp, True)
        source = os.path.join(tmp, "src")
        shutil.copytree(SOURCE, source, ignore=shutil.ignore_patterns("build", "*.egg-info", "__pycache__"))
        target = os.path.join(tmp, "site")
        python = builder_python()
        out = subprocess.run([python, "-m", "pip", "install", "--no-build-isolation", "--no-deps", "--no-index",
                              "--target", target, source], capture_output=True, text=True, timeout=300)
        self.assertEqual(out.returncode, 0, out.stdout + out.stderr)
        self.assertTrue(os.path.exists(os.path.join(target, "anchordb_client.py")))
        self.assertTrue(any(n.startswith("anchordb_client-0.1.0.dist-info") for n in os.listdir(target)))
        server = harness.Server(self)
        script = ("import anchordb_client, sys; c = anchordb_client.Client(sys.argv[1]); c.create_map('pkg');"
                  "print(anchordb_client.__file__); print(c.get_map('pkg')['id'])")
        env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
        env["PYTHONPATH"] = target
        run = subprocess.run([python, "-c", script, server.base_url], capture_output=True, text=True, timeout=60,
                             cwd=tmp, env=env)
        self.assertEqual(run.returncode, 0, run.stderr)
        lines = run.stdout.split()
        self.assertTrue(lines[0].startswith(target), lines)
        self.assertEqual(lines[1], "pkg")


if __name__ == "__main__":
    unittest.main()
