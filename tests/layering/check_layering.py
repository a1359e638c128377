"""SPEC section 2, checked: the dependency direction of the modules (storage/ includes schema/ alone), which library
may link cpp-httplib, that service headers expose neither HTTP nor JSON documents, that services/ names no MIME
type or HTTP header, and that no services/ or storage/ file includes JSON, directly or through a project header.

Usage: check_layering.py SOURCE_DIR LINKS_FILE. LINKS_FILE has one line per library target: "target: dep;dep;..."
(its transitive link closure, written at configure time by tests/CMakeLists.txt). Exits 1 with every violation."""
import os
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]([^">]+)[">]', re.M)
HTTP = ("httplib.h",)
JSON = ("nlohmann/", "schema/json_io.h", "services/common/transitional_json.h")
# A MIME type or an HTTP header's name in a string literal: HTTP detail that services/ hands to api/ typed instead
# (services/common/exported_bytes.h).
HTTP_LITERAL = re.compile(r'"((application|image|text|multipart|audio|video)/[a-z0-9.+-]+|X-[A-Za-z][A-Za-z-]*|'
                          r'Content-(Type|Disposition|Length|Encoding)|Retry-After|Location|Cache-Control|Last-Event-ID)"')
# Modules whose own headers and sources may not include the named prefixes (api -> services -> engine, storage;
# api reaches stored types only through the service headers).
FORBIDDEN = {
    "engine": ("storage/", "services/", "api/", "server/", "sqlite3.h") + HTTP,
    # storage depends on schema/ alone: no engine type in a stored record (issue 30), no engine's header.
    "storage": ("engine/", "services/", "api/", "server/") + HTTP,
    # services reach the database through storage/connection.h only: no engine's header (issue 30).
    "services": ("api/", "server/", "sqlite3.h", "storage/sqlite.h", "libpq-fe.h") + HTTP,
    "api": ("storage/", "server/"),
    "schema": ("engine/", "storage/", "services/", "api/", "server/") + HTTP,
}
# Decision rules moved from services/ (and the forgetting keep rules from storage/) to engine/ (issue 35), by name: the engine header declares the rule, the service
# file calls it, and the service file no longer holds the rule's own code (a pattern of its old body).
MOVED_RULES = (
    # (engine header, rule, service file that uses it, pattern of the old code in services/ or storage/)
    ("engine/forgetting/keep_rules.h", "KeepEvent", "services/jobs/forget_job.cc",
     r"\+\+r\.events_kept_pinned;\s*else if"),
    ("engine/forgetting/keep_rules.h", "KeepKeyframe", "services/jobs/forget_job.cc",
     r"relevance\s*>=\s*\?|\+\+r\.keyframes_kept_pinned;\s*else if"),
    ("engine/segmentation/segment_decisions.h", "SegmentEvidence",
     "services/segmentation/furniture_segmentation_service.cc", r"seen\s*\*\s*5|EvidenceOf\("),
    ("engine/segmentation/segment_decisions.h", "PriorTimesVerification",
     "services/segmentation/furniture_segmentation_service.cc", r"const double floor = 0\.05"),
    ("engine/segmentation/segment_decisions.h", "AverageCategoryShares",
     "services/segmentation/furniture_segmentation_service.cc", r"\*\s*n\s*\+.*\)\s*/\s*\(n\s*\+\s*1"),
    ("engine/segmentation/segment_decisions.h", "MatchSegment",
     "services/segmentation/furniture_segmentation_service.cc", r"best_iou\s*>=|iou\s*>\s*best_iou"),
    ("engine/segmentation/segment_decisions.h", "ParamsForVoxelCentres",
     "services/segmentation/furniture_segmentation_service.cc", r"1\.5\s*\*\s*resolution_m|0\.75\s*\*\s*resolution_m"),
    ("engine/events/labels.h", "FurnitureName", "services/events/event_queries.cc", r"\"furniture\"\s*:"),
    ("engine/features/features.h", "BagOfWordsOfType", "services/classification/object_classification.cc",
     r"words\.push_back\(engine::NearestWord"),
    ("engine/octomap/leaf_centres.h", "LeafCentres", "services/common/capabilities.cc", r"size_m\s*/\s*res"),
)


def moved_rule_problems(root):
    problems = []
    service_code = {}
    for rel in sources(root, "services") + sources(root, "storage"):
        with open(os.path.join(root, rel), encoding="utf-8") as f:
            service_code[rel] = "\n".join(line.split("//", 1)[0] for line in f)
    for header, rule, user, old in MOVED_RULES:
        with open(os.path.join(root, header), encoding="utf-8") as f:
            if not re.search(r"\b%s\(" % rule, f.read()):
                problems.append(f"{header} does not declare the rule {rule}")
        if not re.search(r"\b%s\(" % rule, service_code.get(user, "")):
            problems.append(f"{user} does not use the engine rule {rule} ({header})")
        for rel, code in service_code.items():
            if re.search(old, code):
                problems.append(f"{rel} holds the code of the rule {rule} again (it lives in {header})")
    return problems


# Library targets that must not have cpp-httplib in their link closure: everything but the HTTP edge.
NO_HTTP_TARGETS = ("anchordb_schema", "anchordb_engine", "anchordb_storage", "anchordb_services", "anchordb_server_lib")


def includes(path):
    with open(path, encoding="utf-8") as f:
        return INCLUDE.findall(f.read())


def sources(root, module):
    """Repository-relative paths of the .h and .cc files under `module`."""
    out = []
    for dirpath, _, files in os.walk(os.path.join(root, module)):
        out += [os.path.relpath(os.path.join(dirpath, n), root) for n in files if n.endswith((".h", ".cc"))]
    return sorted(out)


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
    for module in ("services", "storage"):
        for rel in sources(root, module):
            if any(inc.startswith(JSON) for _, inc in transitive_includes(root, rel, set())):
                problems.append(f"{rel} includes JSON ({module}/ may not: JSON is api/'s)")
    for rel in sources(root, "services") + sources(root, "storage"):
        with open(os.path.join(root, rel), encoding="utf-8") as f:
            for number, line in enumerate(f, 1):
                code = line.split("//", 1)[0]
                for m in HTTP_LITERAL.finditer(code):
                    problems.append(f"{rel}:{number} names HTTP detail {m.group(0)} (services/ hand typed metadata to api/)")
    # Public service headers (not *_internal.h): no HTTP, no JSON, also not through another header.
    for dirpath, _, files in os.walk(os.path.join(root, "services")):
        for name in files:
            if not name.endswith(".h") or name.endswith("_internal.h"):
                continue
            rel = os.path.relpath(os.path.join(dirpath, name), root)
            for via, inc in transitive_includes(root, rel, set()):
                if inc.startswith(HTTP + JSON):
                    problems.append(f"service header {rel} reaches {inc} (through {via})")
    problems += moved_rule_problems(root)
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
