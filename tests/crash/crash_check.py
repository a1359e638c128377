"""The checks of the crash campaign (scripts/crash-campaign) after the restart: every acknowledged write of the ledger
against what the restarted server answers, the jobs' outcomes."""

import collections
import os

from crash_load import CAMERA, FRAMES, Connection, harness, ok


class Check:
    """Compares what the restarted server answers with the ledger; counts found writes and lists losses."""

    def __init__(self, trial):
        self.trial, self.conn = trial, Connection(trial)
        self.found, self.losses = collections.Counter(), []

    def get(self, path):
        answer = self.conn.call("GET", path, allowed=(404,))
        return answer[1] if ok(answer) else None

    def expect(self, kind, good, count, what):
        if good:
            self.found[kind] += count
        else:
            self.losses.append(what)

    def run(self):
        t = self.trial
        for m in sorted(t.maps):
            self.expect("maps", self.get("/v1/maps/%s" % m) is not None, 1, "map %s" % m)
        listed = {}
        for m in {key[0] for key in t.layers}:
            for layer in (self.get("/v1/maps/%s/layers" % m) or {"layers": []})["layers"]:
                listed[(m, layer["name"])] = layer
        for key, (base, acked, unanswered) in sorted(t.layers.items()):
            layer = listed.get(key)
            self.expect("layers", layer is not None, 1, "layer %s/%s" % key)
            if layer is None or not acked:
                continue
            kind = "labels" if layer["kind"] == "label" else "obs"
            done = layer["version"] - base
            self.expect(kind, acked <= done <= acked + unanswered, acked,
                        "layer %s/%s: version %d, %d writes acknowledged on version %d (+%d unanswered)" % (
                            key + (layer["version"], acked, base, unanswered)))
            if kind == "labels":
                missing = t.label_names[key] - set(layer["labels"].values())
                if missing:
                    self.losses.append("layer %s/%s: labels %s missing" % (key + (sorted(missing),)))
        for key, state in sorted(t.scenes.items()):
            scene = self.get("/v1/maps/%s/scenes/%d" % key)
            frames = scene["frames"] if scene else -1
            self.expect("frames", state["acked"] <= frames <= state["acked"] + state["unanswered"], state["acked"],
                        "scene %s/%d: %d frames, %d acknowledged (+%d unanswered)" % (
                            key + (frames, state["acked"], state["unanswered"])))
            if state["closed"] and (scene or {}).get("status") != "closed":
                self.losses.append("scene %s/%d: close acknowledged, status %s" % (key + ((scene or {}).get("status"),)))
        for key, state in sorted(t.keyframes.items()):
            kf = self.get("/v1/maps/%s/keyframes/%d" % key)
            self.expect("keyframes", kf is not None, 1, "keyframe %s/%d" % key)
            if state["pinned"]:
                self.expect("pins", kf is not None and kf["pinned"], 1, "keyframe %s/%d: pin" % key)
        for key, state in sorted(t.instances.items()):
            inst = self.get("/v1/maps/%s/instances/%d" % key)
            self.expect("instances", inst is not None, 1, "instance %s/%d" % key)
            if inst is None:
                continue
            top = max(inst["labels"], key=inst["labels"].get) if inst["labels"] else None
            self.expect("labels", top in state["labels"], state["label_acks"],
                        "instance %s/%d: label %s, acknowledged %s" % (key + (top, sorted(state["labels"]))))
            self.expect("pins", inst["pinned"] in state["pinned"], state["pin_acks"],
                        "instance %s/%d: pinned %s, acknowledged %s" % (key + (inst["pinned"], state["pinned"])))
        self.analyses()
        return self.jobs()

    def analyses(self):
        """Every acknowledged keyframe (except the forgetting's targets) that is still stored has its change analysis
        written: the analyses of a map run in keyframe order, so once a new keyframe of the map, posted with
        wait_for_analysis=true, says done, the map's queue must be empty and have no failures."""
        by_map = collections.defaultdict(list)
        for key in self.trial.keyframes:
            by_map[key[0]].append(key)
        for m, keys in sorted(by_map.items()):
            present = [key for key in keys if self.get("/v1/maps/%s/keyframes/%d" % key) is not None]
            scene = self.conn.call("POST", "/v1/maps/%s/scenes" % m, {
                "camera": CAMERA, "pose": {"position": [9.0, 0.0, 1.0], "orientation": [0, 0, 0, 1]}, "merge": False})
            waited = ok(scene) and self.conn.call(
                "POST", "/v1/maps/%s/scenes/%d/frames?wait_for_analysis=true" % (m, scene[1]["id"]), FRAMES[0])
            state = waited[1].get("analysis", {}).get("state") if ok(waited) else None
            queue = self.get("/v1/maps/%s/analysis" % m)
            good = state == "done" and queue is not None and queue["depth"] == 0 and queue["failed"] == 0
            self.expect("analyses", good, len(present),
                        "map %s: analyses not all done after the restart (waited keyframe %s, queue %s)" % (m, state, queue))

    def jobs(self):
        """Job outcomes: (summary text, problems)."""
        t, out, problems = self.trial, [], []
        jobs = {}
        for job in (self.get("/v1/jobs/%d" % j) for j in range(1, 4)):
            if job is not None:
                jobs[job["kind"]] = job
        for kind in ("forget", "backup"):
            if kind in t.jobs and kind not in jobs:
                problems.append("%s job %d acknowledged, not found" % (kind, t.jobs[kind]))
            job = jobs.get(kind)
            if job is not None and job["status"] not in ("succeeded", "failed"):
                problems.append("%s job %d still %s after the restart" % (kind, job["id"], job["status"]))
            if job is not None and job["status"] == "failed" and "interrupted" not in (job["error"] or ""):
                problems.append("%s job %d failed: %s" % (kind, job["id"], job["error"]))
        left = {kf for kf in t.old_keyframes if self.get("/v1/maps/%s/keyframes/%d" % kf) is not None}
        forget = jobs.get("forget")
        applied = forget is not None and (forget["status"] == "succeeded" or bool((forget["result"] or {}).get("committed")))
        before = len(problems)
        if left and left != t.old_keyframes:
            problems.append("forgetting half-applied: %d of %d old keyframes left" % (len(left), len(t.old_keyframes)))
        elif applied and left:
            problems.append("forgetting job %s says applied, %d old keyframes left" % (forget["status"], len(left)))
        elif not applied and t.old_keyframes and not left:
            problems.append("old keyframes gone, the forgetting job says %s" % (forget or {}).get("status"))
        if len(problems) == before:  # the old keyframes are accounted for: all there, or all forgotten
            self.found["keyframes"] += len(t.old_keyframes)
        out.append("F:%s/%s" % ((forget or {}).get("status", "-")[:4], "all" if applied else "none"))
        out.append("B:" + self.backup(jobs.get("backup"), problems))
        return " ".join(out), problems

    def backup(self, job, problems):
        """Every backup file is complete and valid; a succeeded job's file exists with its size."""
        folder = os.path.join(self.trial.server.tmpdir, "backups")
        files = sorted(f for f in os.listdir(folder) if f.endswith(".sqlite")) if os.path.isdir(folder) else []
        for f in files:
            integrity, fk = harness.soundness(os.path.join(folder, f))
            if integrity != "ok" or fk:
                problems.append("backup file %s: integrity %s, fk %s" % (f, integrity, fk))
        if job is None:
            return "-"
        if job["status"] == "succeeded":
            path = job["result"]["file"]
            if not os.path.isfile(path) or os.path.getsize(path) != job["result"]["bytes"]:
                problems.append("backup job succeeded, file %s missing or not %d bytes" % (path, job["result"]["bytes"]))
            return "succ/file"
        return "%s/%s" % (job["status"][:4], "file" if os.path.isfile(job["request"]["file"]) else "none")
