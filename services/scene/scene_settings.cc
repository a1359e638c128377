#include "services/scene/scene_settings.h"

namespace anchordb::services {

void BindSceneSettings(SettingsBinder& b, SceneLimits& scene, MergeSettings& merge) {
  b.Bind("scene_persist_every_frames", "frames between checkpoints of an observing scene model (the frame journal "
         "replayed when a model is loaded after a restart holds at most this many frames)", &scene.persist_every_frames, 1, 1e6);
  b.Bind("scene_frame_journal", "commit every frame to the frame journal before answering it, so that every "
         "acknowledged frame survives a crash; false: only checkpoints are durable (kept for the ingest bench)",
         &scene.frame_journal);
  b.Bind("scene_max_image_side", "largest camera width or height of a scene model [px]", &scene.max_image_side, 1, 16384);
  b.Bind("scene_settle_frames", "steady frames after a change of the movable layer that make a 'settled' keyframe "
         "(a completed movement, new action layer); 0 = off", &scene.settle_frames, 0, 1e6);
  b.Bind("scene_settle_min_change_px", "movable pixels that must change (or background pixels reset farther) before "
         "a movement can settle [px]", &scene.settle_min_change_px, 1, 1e8);
  b.Bind("scene_settle_tolerance_px", "change of the movable layer per frame that still counts as steady [px]",
         &scene.settle_tolerance_px, 0, 1e8);
  b.Bind("merge_max_candidates", "most earlier scene models merged into a new one (newest first)", &merge.max_candidates, 0, 100);
  b.Bind("merge_max_age_s", "earlier scene models older than this are not merged [s]", &merge.max_age_s, 0, 1e10);
  b.Bind("merge_candidate_radius_m", "earlier cameras farther than this from the new one are not merged [m]",
         &merge.candidate_radius_m, 0, 1000);
  b.Bind("merge_min_overlap", "fraction of an earlier background that must lie in the new view frustum", &merge.min_overlap, 0, 1);
  b.Bind("merge_frustum_far_m", "rear boundary of a view frustum, for overlap and rear projection [m]", &merge.frustum_far_m, 0.5, 50);
  b.Bind("supersede_distance_m", "a new scene model this close to an earlier one (and looking alike) supersedes it [m]",
         &merge.supersede_distance_m, 0, 10);
  b.Bind("scene_pose_sigma_translation_m", "the localisation error of a scene model's camera position when the client "
         "gives no pose_sigma or pose_covariance (standard deviation per map axis) [m]", &merge.pose_sigma_translation_m, 0, 10);
  b.Bind("scene_pose_sigma_rotation_rad", "the same for its orientation (standard deviation about each map axis) [rad]",
         &merge.pose_sigma_rotation_rad, 0, 3.1416);
  b.Bind("supersede_angle_rad", "largest angle between viewing directions for supersession [rad]", &merge.supersede_angle_rad, 0, 3.1416);
}

}  // namespace anchordb::services
