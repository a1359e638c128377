#include "engine/events/keyframe_analysis.h"

#include <algorithm>

#include "engine/events/sentences.h"

namespace anchordb::engine {
namespace {

// Builds a change set while keeping the analysis' view of the instances current: an instance removed earlier in
// the same change set is a lost-key candidate for a later addition.
class ChangeBuilder {
 public:
  ChangeBuilder(const std::vector<KnownInstance>& instances, const EventRules& rules) : working_(instances), rules_(rules) {
    for (std::size_t i = 0; i < working_.size(); ++i) {
      if (!working_[i].present) continue;
      present_.push_back(working_[i]);
      present_at_.push_back(i);
    }
    taken_.assign(present_.size(), false);
  }

  // Index of the present instance the segment is (taken from now on), or -1.
  int Match(const Segment& s) {
    ++out_.segments_examined;
    const int m = BestMatch(s, present_, taken_, rules_.match);
    if (m >= 0) taken_[static_cast<std::size_t>(m)] = true;
    return m;
  }
  const KnownInstance& Present(int m) const { return present_[static_cast<std::size_t>(m)]; }
  std::size_t PresentCount() const { return present_.size(); }
  bool Taken(std::size_t m) const { return taken_[m]; }

  int KeepSegment(std::int64_t keyframe_id, const Segment& s) {
    out_.segments.push_back({keyframe_id, s});
    return static_cast<int>(out_.segments.size() - 1);
  }

  // The segment is the present instance m, seen again.
  void Confirm(int m, const Segment& s, std::int64_t stamp_ns, std::int64_t scene_id) {
    const KnownInstance& r = Present(m);
    InstanceUpdate u;
    u.instance = Ref::Existing(r.id);
    u.last_seen_ns = std::max(r.last_seen_ns, stamp_ns);
    u.last_scene_id = scene_id;
    u.sample_m = s.sample_m;
    u.touch = true;
    out_.updates.push_back(std::move(u));
  }

  Ref NewInstance(const Segment& s, bool present, std::int64_t last_seen_ns, std::int64_t scene_id) {
    out_.new_instances.push_back({present, s.centroid_m, s.Extent(), s.sample_m, last_seen_ns, scene_id});
    return Ref::New(out_.new_instances.size() - 1);
  }

  Ref AddEvent(NewEvent e) {
    out_.events.push_back(std::move(e));
    return Ref::New(out_.events.size() - 1);
  }

  void AppendHistory(Ref instance, std::int64_t stamp_ns, bool present, const Eigen::Vector3d& p_m, std::optional<Ref> event) {
    out_.history.push_back({instance, stamp_ns, present, p_m, event});
    if (instance.is_new()) return;
    for (KnownInstance& w : working_) {
      if (w.id == instance.id) w.last_history = HistoryPoint{stamp_ns, present, p_m, event};
    }
  }

  // The present instance m is gone (status absent from now on).
  void MarkAbsent(int m) {
    InstanceUpdate u;
    u.instance = Ref::Existing(Present(m).id);
    u.present = false;
    u.touch = true;
    out_.updates.push_back(std::move(u));
    working_[present_at_[static_cast<std::size_t>(m)]].present = false;
  }

  // An object added (kept as segment `segment`): a new instance, or by the lost-key rule a labelled one moved.
  void Added(const Segment& s, int segment, Detection detection, std::int64_t stamp_ns, std::int64_t scene_id,
             std::int64_t layer, std::vector<Evidence> evidence) {
    NewEvent e;
    e.detection = detection;
    e.stamp_ns = stamp_ns;
    e.scene_id = scene_id;
    e.action_layer = layer;
    e.segment = segment;
    e.evidence = std::move(evidence);
    e.segment_summary = Summarise(s);
    const auto moved = detection == Detection::kObserved
                           ? LostKeyMove(s.Extent(), working_, stamp_ns, rules_.move_min_size_similarity)
                           : std::nullopt;
    if (moved) {
      KnownInstance& r = working_[static_cast<std::size_t>(moved->index)];
      const HistoryPoint removal = *r.last_history;
      const std::string top = TopLabel(r.labels);
      e.type = EventType::kMoved;
      e.label = top;
      e.explanation = MoveExplanation(top, r.id, removal.position_m, s.centroid_m, moved->size_similarity);
      e.move = MoveDetails{removal.position_m, moved->size_similarity, removal.event};
      e.instance = Ref::Existing(r.id);
      InstanceUpdate u;
      u.instance = e.instance;
      u.present = true;
      u.position_m = s.centroid_m;
      u.extent_m = s.Extent();
      u.last_seen_ns = stamp_ns;
      u.last_scene_id = scene_id;
      u.sample_m = s.sample_m;
      u.touch = true;
      out_.updates.push_back(std::move(u));
      r.present = true;
      r.position_m = s.centroid_m;
      r.extent_m = s.Extent();
    } else {
      e.type = EventType::kAdded;
      e.instance = NewInstance(s, true, stamp_ns, scene_id);
      e.explanation = AddedExplanation(detection);
    }
    const Ref instance = e.instance;
    const Ref event = AddEvent(std::move(e));
    AppendHistory(instance, stamp_ns, true, s.centroid_m, event);
  }

  ChangeSet Take() { return std::move(out_); }
  ChangeSet& changes() { return out_; }

 private:
  std::vector<KnownInstance> working_;  // every known instance as the change set leaves it
  std::vector<KnownInstance> present_;  // those present at the start (matching candidates)
  std::vector<std::size_t> present_at_;
  std::vector<bool> taken_;
  const EventRules& rules_;
  ChangeSet out_;
};

}  // namespace

SegmentSummary Summarise(const Segment& s) { return {s.centroid_m, s.Extent(), s.points}; }

const char* EventTypeName(EventType type) {
  switch (type) {
    case EventType::kAdded: return "added";
    case EventType::kRemoved: return "removed";
    case EventType::kMoved: return "moved";
  }
  return "added";
}

const char* DetectionName(Detection detection) {
  switch (detection) {
    case Detection::kObserved: return "observed";
    case Detection::kMeanwhile: return "meanwhile";
    case Detection::kReanalysis: return "reanalysis";
  }
  return "observed";
}

ChangeSet AnalyseBeginKeyframe(const BeginKeyframe& k, const std::vector<KnownInstance>& instances, const EventRules& rules) {
  ChangeBuilder b(instances, rules);
  for (const Segment& s : k.front_segments) {
    const int match = b.Match(s);
    if (match >= 0) {
      b.Confirm(match, s, k.stamp_ns, k.scene_id);
      continue;
    }
    const int segment = b.KeepSegment(k.keyframe_id, s);
    std::vector<Evidence> evidence;
    for (std::int64_t before : k.before_keyframes) evidence.push_back({before, "before"});
    evidence.push_back({k.keyframe_id, "after"});
    b.Added(s, segment, Detection::kMeanwhile, k.stamp_ns, k.scene_id, 0, std::move(evidence));
  }
  // Objects believed present that this view sees through were removed meanwhile.
  for (std::size_t i = 0; i < b.PresentCount(); ++i) {
    if (b.Taken(i)) continue;
    const int m = static_cast<int>(i);
    const KnownInstance& r = b.Present(m);
    const Visibility v = CheckVisibility(r.sample_m, k.depth_mm, k.K, k.X_MapCamera, k.change);
    const SeenThrough judged = JudgeSeenThrough(v, rules.removed_min_seen_through, rules.removed_min_visible_points);
    if (judged == SeenThrough::kSeenAgain) {
      InstanceUpdate u;
      u.instance = Ref::Existing(r.id);
      u.last_seen_ns = k.stamp_ns;
      b.changes().updates.push_back(std::move(u));
    }
    if (judged != SeenThrough::kRemoved) continue;
    NewEvent e;
    e.type = EventType::kRemoved;
    e.detection = Detection::kMeanwhile;
    e.stamp_ns = k.stamp_ns;
    e.scene_id = k.scene_id;
    e.action_layer = 0;
    e.instance = Ref::Existing(r.id);
    if (r.last_keyframe_id) e.evidence.push_back({*r.last_keyframe_id, "before"});
    e.evidence.push_back({k.keyframe_id, "after"});
    e.explanation = SeenThroughExplanation(v.seen_through, v.confirmed + v.seen_through, r.position_m);
    e.visibility = v;
    const Ref event = b.AddEvent(std::move(e));
    const Eigen::Vector3d position_m = r.position_m;
    const std::int64_t id = r.id;
    b.MarkAbsent(m);
    b.AppendHistory(Ref::Existing(id), k.stamp_ns, false, position_m, event);
  }
  return b.Take();
}

ChangeSet AnalyseLayerKeyframe(const LayerKeyframe& k, const std::vector<KnownInstance>& instances, const EventRules& rules) {
  ChangeBuilder b(instances, rules);
  // Removals first: an object taken and put back elsewhere in one layer is then a removal and an addition.
  for (const Segment& s : k.removed_segments) {
    const int segment = b.KeepSegment(k.opening_keyframe_id, s);
    const int match = b.Match(s);
    Ref instance;
    Eigen::Vector3d position_m = s.centroid_m;
    if (match >= 0) {
      if (b.Present(match).status_locked) continue;
      instance = Ref::Existing(b.Present(match).id);
      position_m = b.Present(match).position_m;
    } else {  // part of the background until now: an instance from here on
      instance = b.NewInstance(s, false, k.opening_stamp_ns, k.scene_id);
      b.AppendHistory(instance, k.opening_stamp_ns, true, s.centroid_m, std::nullopt);
    }
    NewEvent e;
    e.type = EventType::kRemoved;
    e.detection = Detection::kObserved;
    e.stamp_ns = k.stamp_ns;
    e.scene_id = k.scene_id;
    e.action_layer = k.action_layer;
    e.instance = instance;
    e.segment = segment;
    e.evidence = {{k.opening_keyframe_id, "before"}, {k.keyframe_id, "after"}};
    e.explanation = RemovedObservedExplanation();
    e.segment_summary = Summarise(s);
    const Ref event = b.AddEvent(std::move(e));
    if (match >= 0) b.MarkAbsent(match);
    b.AppendHistory(instance, k.stamp_ns, false, position_m, event);
  }
  for (const Segment& s : k.added_segments) {
    const int match = b.Match(s);
    if (match >= 0) {  // already known here (e.g. found at the begin keyframe)
      b.Confirm(match, s, k.stamp_ns, k.scene_id);
      continue;
    }
    const int segment = b.KeepSegment(k.keyframe_id, s);
    b.Added(s, segment, Detection::kObserved, k.stamp_ns, k.scene_id, k.action_layer,
            {{k.opening_keyframe_id, "before"}, {k.keyframe_id, "after"}});
  }
  return b.Take();
}

Reanalysis ReanalyseKeyframe(const ReanalysedKeyframe& k, const std::vector<InstanceAtTime>& instances, const MatchParams& match) {
  Reanalysis out;
  ChangeSet& c = out.changes;
  for (const Segment& s : k.segments) {
    ++c.segments_examined;
    std::optional<std::int64_t> known;
    for (const InstanceAtTime& r : instances) {
      if (r.at_keyframe && r.at_keyframe->present && Matches(s, r.at_keyframe->position_m, r.extent_m, match)) known = r.id;
    }
    out.known_instance.push_back(known);
    if (known) continue;
    // Missed when the keyframe was taken: it stood there then, and the newer background shows the place without it.
    c.segments.push_back({k.keyframe_id, s});
    c.new_instances.push_back({false, s.centroid_m, s.Extent(), s.sample_m, k.stamp_ns, k.scene_id});
    const Ref instance = Ref::New(c.new_instances.size() - 1);
    NewEvent added;
    added.type = EventType::kAdded;
    added.detection = Detection::kReanalysis;
    added.stamp_ns = k.stamp_ns;
    added.scene_id = k.scene_id;
    added.action_layer = k.action_layer;
    added.instance = instance;
    added.segment = static_cast<int>(c.segments.size() - 1);
    added.evidence = {{k.keyframe_id, "after"}};
    added.explanation = ReanalysisAddedExplanation(k.keyframe_id, k.background_scene_id);
    added.segment_summary = Summarise(s);
    added.background_scene = k.background_scene_id;
    NewEvent removed = added;
    removed.type = EventType::kRemoved;
    removed.stamp_ns = std::max(k.background_stamp_ns, k.stamp_ns);
    removed.scene_id = k.background_scene_id;
    removed.action_layer = std::nullopt;
    removed.evidence = {{k.keyframe_id, "before"}};
    if (k.background_keyframe_id) removed.evidence.push_back({*k.background_keyframe_id, "after"});
    removed.explanation = ReanalysisRemovedExplanation(k.background_scene_id);
    c.events.push_back(std::move(added));
    c.history.push_back({instance, k.stamp_ns, true, s.centroid_m, Ref::New(c.events.size() - 1)});
    c.events.push_back(std::move(removed));
    c.history.push_back({instance, c.events.back().stamp_ns, false, s.centroid_m, Ref::New(c.events.size() - 1)});
  }
  return out;
}

}  // namespace anchordb::engine
