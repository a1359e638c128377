#include "services/furniture/furniture_settings.h"

namespace anchordb::services {

void BindFurnitureSettings(SettingsBinder& b, FurnitureSettings& f) {
  b.Bind("grounding_n_best", "hypotheses (graph, match) a furniture graph keeps per description (thesis 5.3.3; default of "
         "params.n_best)", &f.n_best, 1, 2000);
  b.Bind("grounding_sigma", "damping of the grounding update p += (p_verbal - p) / sigma (thesis eq. 5.4; 1 = replace)",
         &f.sigma, 1, 1000);
  b.Bind("grounding_edge_max_gap_m", "furniture pieces whose footprints are at most this far apart share a graph edge [m]",
         &f.edge_max_gap_m, 0, 100);
  b.Bind("grounding_relation_sharpness", "kappa of the initial relation distribution p(r) ∝ exp(kappa cos(angle))",
         &f.relation_sharpness, 0, 100);
  b.Bind("grounding_ambiguity_margin", "a description is ambiguous (its category update held back until resolved) when a "
         "reading of other pieces is within this much accumulated score (eq. 5.2) of the best; 0 = off", &f.ambiguity_margin, 0, 10);
  b.Bind("grounding_model", "how new furniture graphs score their hypotheses (default of params.model): joint (the "
         "log-joint of a hypothesis' descriptions, engine/grounding/joint_model.h; the default, it meets issue 17's bars) "
         "or sequential (the thesis' sum of eq. 5.2 on damped updates)", &f.model);
  b.Require([&f] { return f.model == "sequential" || f.model == "joint"; }, "grounding_model must be sequential or joint");
  b.Bind("grounding_ambiguity_margin_joint", "the same margin for graphs of the joint model, in nats of its log-joint; 0 = off",
         &f.ambiguity_margin_joint, 0, 10);
  b.Bind("grounding_category_floor", "a description moves a piece's p(f) only towards a category the piece already holds "
         "with at least this probability (0.05 = half the chance level of 10 categories; a second description naming the piece so confirms; 0 = always, the thesis)", &f.category_floor, 0, 1);
  b.Bind("grounding_max_furniture", "most furniture pieces in one furniture graph", &f.max_furniture, 2, 1000);
}

}  // namespace anchordb::services
