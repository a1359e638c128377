"""The layering check fails on each kind of violation planted into a copy of the tree, and passes on the copy as it is.

Usage: test_check_layering.py SOURCE_DIR LINKS_FILE (as check_layering.py)."""
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

SOURCE_DIR, LINKS_FILE = sys.argv[1], sys.argv[2]
CHECK = os.path.join(os.path.dirname(os.path.abspath(__file__)), "check_layering.py")
MODULES = ("schema", "engine", "storage", "services", "api", "server")


class PlantedViolations(unittest.TestCase):
    def setUp(self):
        self.root = tempfile.mkdtemp(prefix="layering-")
        for m in MODULES:
            shutil.copytree(os.path.join(SOURCE_DIR, m), os.path.join(self.root, m),
                            ignore=shutil.ignore_patterns("*.png", "*.json", "*.yaml", "*.md"))

    def tearDown(self):
        shutil.rmtree(self.root)

    def check(self):
        r = subprocess.run([sys.executable, CHECK, self.root, LINKS_FILE], capture_output=True, text=True)
        return r.returncode, r.stdout

    def plant(self, rel, text):
        with open(os.path.join(self.root, rel), "a", encoding="utf-8") as f:
            f.write(text)

    def assert_fails(self, rel, text, expected):
        self.plant(rel, text)
        code, out = self.check()
        self.assertEqual(code, 1, out)
        self.assertIn(expected, out)

    def test_the_tree_as_it_is_passes(self):
        code, out = self.check()
        self.assertEqual(code, 0, out)

    def test_json_in_a_service(self):
        self.assert_fails("services/common/cloud_bytes.cc", '\n#include <nlohmann/json.hpp>\n',
                          "services/common/cloud_bytes.cc includes JSON")

    def test_json_through_schema_in_storage(self):
        self.assert_fails("storage/blob_codec.cc", '\n#include "schema/json_io.h"\n', "storage/blob_codec.cc includes JSON")

    def test_engine_header_in_storage(self):
        self.assert_fails("storage/blob_codec.cc", '\n#include "engine/grounding/grounding.h"\n',
                          "storage/blob_codec.cc includes engine/grounding/grounding.h (storage/ may not)")

    def test_database_engine_header_in_a_service(self):
        self.assert_fails("services/common/cloud_bytes.cc", '\n#include "storage/sqlite.h"\n',
                          "includes storage/sqlite.h (services/ may not)")
        self.plant("services/common/cloud_bytes.h", '\n#include <libpq-fe.h>\n')
        self.assertIn("includes libpq-fe.h (services/ may not)", self.check()[1])

    def test_mime_type_and_header_names_in_a_service(self):
        self.assert_fails("services/common/cloud_bytes.cc", '\nconst char* kType = "image/png";\n',
                          'names HTTP detail "image/png"')
        self.plant("services/common/cloud_bytes.cc", '\nconst char* kName = "X-Points";\n')
        self.assertIn('names HTTP detail "X-Points"', self.check()[1])

if __name__ == "__main__":
    unittest.main(argv=[sys.argv[0]], verbosity=2)
