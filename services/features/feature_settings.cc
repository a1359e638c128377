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
  b.Bind("features_max_codebook_words", "most words of one codebook", &f.max_codebook_words, 2, 100000);
}

}  // namespace anchordb::services
