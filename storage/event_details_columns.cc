#include "storage/event_details_columns.h"

#include "schema/error.h"

namespace anchordb::storage::event_details {

const char* const kColumns =
    "segment_centroid_x_m, segment_centroid_y_m, segment_centroid_z_m, segment_extent_x_m, segment_extent_y_m, "
    "segment_extent_z_m, segment_points, moved_from_x_m, moved_from_y_m, moved_from_z_m, move_size_similarity, "
    "move_removal_event, visibility_outside, visibility_confirmed, visibility_seen_through, visibility_hidden, "
    "visibility_unmeasured, background_scene, label_weight_rows";

namespace {

std::array<double, 3> Vec3(const Statement& s, int first) { return {s.Double(first), s.Double(first + 1), s.Double(first + 2)}; }

void BindVec3(Statement& s, int first, const std::array<double, 3>* v) {
  for (int i = 0; i < 3; ++i) {
    if (v) s.Bind(first + i, (*v)[static_cast<std::size_t>(i)]);
    else s.BindNull(first + i);
  }
}

template <typename T>
void BindOr(Statement& s, int index, bool present, T value) {
  if (present) s.Bind(index, value);
  else s.BindNull(index);
}

}  // namespace

std::int64_t Read(const Statement& s, int f, EventDetailsRecord& d) {
  if (!s.IsNull(f + 6)) d.segment = EventSegmentDetails{Vec3(s, f), Vec3(s, f + 3), s.Int(f + 6)};
  if (!s.IsNull(f + 7)) d.move = EventMoveDetails{Vec3(s, f + 7), s.Double(f + 10), OptionalInt(s, f + 11)};
  if (!s.IsNull(f + 12)) {
    d.visibility = EventVisibilityDetails{s.Int(f + 12), s.Int(f + 13), s.Int(f + 14), s.Int(f + 15), s.Int(f + 16)};
  }
  d.background_scene = OptionalInt(s, f + 17);
  if (s.IsNull(f + 18)) return 0;
  d.label_weights.emplace();
  return s.Int(f + 18);
}

void Bind(Statement& s, int f, const EventDetailsRecord& d) {
  const EventSegmentDetails* segment = d.segment ? &*d.segment : nullptr;
  BindVec3(s, f, segment ? &segment->centroid_m : nullptr);
  BindVec3(s, f + 3, segment ? &segment->extent_m : nullptr);
  BindOr(s, f + 6, segment != nullptr, segment ? segment->points : 0);
  const EventMoveDetails* move = d.move ? &*d.move : nullptr;
  BindVec3(s, f + 7, move ? &move->from_m : nullptr);
  BindOr(s, f + 10, move != nullptr, move ? move->size_similarity : 0.0);
  BindOptional(s, f + 11, move ? move->removal_event : std::nullopt);
  const EventVisibilityDetails* v = d.visibility ? &*d.visibility : nullptr;
  BindOr(s, f + 12, v != nullptr, v ? v->outside : 0);
  BindOr(s, f + 13, v != nullptr, v ? v->confirmed : 0);
  BindOr(s, f + 14, v != nullptr, v ? v->seen_through : 0);
  BindOr(s, f + 15, v != nullptr, v ? v->hidden : 0);
  BindOr(s, f + 16, v != nullptr, v ? v->unmeasured : 0);
  BindOptional(s, f + 17, d.background_scene);
  BindOr(s, f + 18, d.label_weights.has_value(),
         static_cast<std::int64_t>(d.label_weights ? d.label_weights->size() : 0));
}

void LoadLabelWeights(Connection& c, std::int64_t event_id, EventDetailsRecord& d) {
  Statement s(c, "SELECT label, weight FROM event_label_weights WHERE event_id = ? ORDER BY label");
  s.Bind(1, event_id);
  auto& weights = d.label_weights.emplace();
  while (s.Step()) weights[s.Text(0)] = s.Double(1);
}

void InsertLabelWeights(Connection& c, std::int64_t event_id, const EventDetailsRecord& d) {
  if (!d.label_weights) return;
  for (const auto& [label, weight] : *d.label_weights) {
    Statement(c, "INSERT INTO event_label_weights (event_id, label, weight) VALUES (?, ?, ?)")
        .Bind(1, event_id).Bind(2, label).Bind(3, weight).Run();
  }
}

}  // namespace anchordb::storage::event_details
