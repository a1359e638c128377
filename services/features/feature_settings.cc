#include "services/features/feature_settings.h"

namespace anchordb::services {

void BindFeatureSettings(SettingsBinder& b, FeatureSettings& f) {
  struct Typed {
    const char* type;
    engine::DedupThreshold* t;
  };
  for (const Typed& x : {Typed{"fpfh", &f.fpfh}, Typed{"shot", &f.shot}, Typed{"spd", &f.spd}, Typed{"other", &f.other}}) {
    const std::string type = x.type;
    const std::string which = type == "other" ? "client types (x_*, orb, ...)" : type;
    b.Bind("features_dedup_radius_m_" + type, "a new " + which + " feature this close to a stored one of its type [m] "
           "and within the descriptor distance is a duplicate (thesis 4.3.2)", &x.t->radius_m, 0, 10);
    b.Bind("features_dedup_descriptor_" + type, "descriptor (Euclidean) distance under which a close " + which +
           " feature is a duplicate (0: only exact repeats)", &x.t->descriptor_distance, 0, 1e6);
  }
  b.Bind("features_max_batch", "most features in one client batch", &f.max_batch, 1, 1000000);
  b.Bind("features_extract_every_keyframe", "extract fpfh, shot and spd from every new keyframe after its write (a worker "
         "thread outside the write lock)", &f.extract_every_keyframe);
  b.Bind("features_extract_voxel_m", "extraction thins the keyframe cloud to this voxel size [m]", &f.extraction.voxel_m, 0.002, 1);
  b.Bind("features_extract_normal_radius_m", "radius of the normal estimate [m]", &f.extraction.normal_radius_m, 0.005, 2);
  b.Bind("features_extract_feature_radius_m", "support radius of FPFH and SHOT [m]", &f.extraction.feature_radius_m, 0.01, 5);
  b.Bind("features_extract_keypoint_voxel_m", "one FPFH/SHOT keypoint per voxel of this size [m]", &f.extraction.keypoint_voxel_m,
         0.01, 5);
  b.Bind("features_extract_max_planes", "most RANSAC planes (spd) per keyframe", &f.extraction.max_planes, 0, 100);
  b.Bind("features_max_codebook_words", "most words of one codebook", &f.max_codebook_words, 2, 100000);
}

}  // namespace anchordb::services
