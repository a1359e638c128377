"""SPEC section 2, checked: the dependency direction of the modules, which library may link cpp-httplib, and that
service headers expose neither HTTP nor JSON documents.

Usage: check_layering.py SOURCE_DIR LINKS_FILE. LINKS_FILE has one line per library target: "target: dep;dep;..."
(its transitive link closure, written at configure time by tests/CMakeLists.txt). Exits 1 with every violation."""
import os
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]([^">]+)[">]', re.M)
HTTP = ("httplib.h",)
JSON = ("nlohmann/", "schema/json_io.h", "services/common/transitional_json.h")
# Modules whose own headers and sources may not include the named prefixes (api -> services -> engine, storage;
# api reaches stored types only through the service headers).
FORBIDDEN = {
    "engine": ("storage/", "services/", "api/", "server/", "sqlite3.h") + HTTP,
    "storage": ("services/", "api/", "server/") + HTTP,
    # services reach the database through storage/connection.h only: no engine's header (issue 30).
    "services": ("api/", "server/", "sqlite3.h", "storage/sqlite.h", "libpq-fe.h") + HTTP,
    "api": ("storage/", "server/"),
    "schema": ("engine/", "storage/", "services/", "api/", "server/") + HTTP,
}
# Library targets that must not have cpp-httplib in their link closure: everything but the HTTP edge.
NO_HTTP_TARGETS = ("anchordb_schema", "anchordb_engine", "anchordb_storage", "anchordb_services", "anchordb_server_lib")


def includes(path):
    with open(path, encoding="utf-8") as f:
        return INCLUDE.findall(f.read())


def transitive_includes(root, header, seen):
    """Project headers reachable from `header` (repository-relative), and every include line met on the way."""
    found = []
    for inc in includes(os.path.join(root, header)):
        found.append((header, inc))
        if os.path.isfile(os.path.join(root, inc)) and inc not in seen:
            seen.add(inc)
            found += transitive_includes(root, inc, seen)
    return found


def main():
    root, links_file = sys.argv[1], sys.argv[2]
    problems = []
    for module, banned in FORBIDDEN.items():
        for dirpath, _, files in os.walk(os.path.join(root, module)):
            for name in files:
                if not name.endswith((".h", ".cc")):
                    continue
                rel = os.path.relpath(os.path.join(dirpath, name), root)
                for inc in includes(os.path.join(root, rel)):
                    if inc.startswith(banned):
                        problems.append(f"{rel} includes {inc} ({module}/ may not)")
    # Public service headers (not *_internal.h): no HTTP, no JSON, also not through another header.
    for dirpath, _, files in os.walk(os.path.join(root, "services")):
        for name in files:
            if not name.endswith(".h") or name.endswith("_internal.h"):
                continue
            rel = os.path.relpath(os.path.join(dirpath, name), root)
            for via, inc in transitive_includes(root, rel, set()):
                if inc.startswith(HTTP + JSON):
                    problems.append(f"service header {rel} reaches {inc} (through {via})")
    with open(links_file, encoding="utf-8") as f:
        links = dict(line.rstrip("\n").split(": ", 1) for line in f if ": " in line)
    for target in NO_HTTP_TARGETS:
        if target not in links:
            problems.append(f"{target} is missing from {links_file}")
        elif "HTTPLIB" in links[target].upper():
            problems.append(f"{target} links cpp-httplib: {links[target]}")
    if "HTTPLIB" not in links.get("anchordb_api", "").upper():
        problems.append("anchordb_api does not link cpp-httplib (is the links file stale?)")
    for p in sorted(set(problems)):
        print(p)
    print(f"layering: {len(set(problems))} violation(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
