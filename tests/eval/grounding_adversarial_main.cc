// Prints the adversarial grounding evaluation of issue 17 as the issue's table: the thesis model, issue 17's
// sequential model and the joint model in the same run, per speaker type and quality, with the worst room; the table
// of each block of --rooms seeds, then the blocks pooled (the mean over rooms) beside the worst block per cell:
// separately for the blocks before --held_out_from (seeds the joint model's constants and rules were chosen on or
// looked at: 1-30 for the constants, 31-120 for the repeat rule) and from it on (held out), then all of them.
//   anchordb_eval_grounding_adversarial [--rooms N] [--seed S] [--blocks B] [--held_out_from S]
//       [--models thesis,issue17,joint] [--slack X] [--sight X] [--proximity_m X] [--strength X] [--noise X]
//       [--repeat X] [--margin X] [--floor X] [--failures 1]
// Defaults: 8 blocks of 30 rooms per speaker type from seed 1 (seeds 1-240), held out from 121, every model.
// --failures 1 traces every room whose graph the joint model ends with a piece wrong (stderr). The other options
// change the joint model's parameters (JointOptions() otherwise).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "tests/eval/grounding_adversarial.h"

using namespace anchordb::eval::adversarial;

namespace {

void PrintTable(const Table& t, const std::vector<Model>& models) {
  std::printf("%-10s | %-14s | %-34s | %-34s\n", "speakers", "model", "quality A", "quality B (one piece misclassified)");
  for (int s = 0; s < 3; ++s) {
    for (const Model m : models) {
      std::printf("%-10s | %-14s |", SpeakerName(static_cast<Speaker>(s)), ModelName(m));
      for (int q = 0; q < 2; ++q) {
        const Cell& c = t.cells[static_cast<int>(m)][q][s];
        std::printf(" %4.2f / %4.2f (worst room %4.2f)         |", c.GraphRate(), c.DescriptionRate(), c.worst_room_rate);
      }
      std::printf("\n");
    }
  }
  for (const Model m : models) {
    const Cell a = t.Over(m, 0), b = t.Over(m, 1);
    std::printf("all speakers, %-12s: A %4.2f / %4.3f, B %4.2f / %4.3f, descriptions overall %5.3f\n", ModelName(m),
                a.GraphRate(), a.DescriptionRate(), b.GraphRate(), b.DescriptionRate(), t.DescriptionRate(m));
  }
}

// Every block pooled (the mean over rooms) beside the worst block, per cell.
void PrintPooled(const std::vector<Table>& blocks, const std::vector<Model>& models) {
  std::printf("%-10s | %-14s | %-42s | %-42s\n", "speakers", "model", "quality A: graphs / descr. (worst block)",
              "quality B: graphs / descr. (worst block)");
  const auto line = [&](const char* who, Model m, const auto& cell_of) {
    std::printf("%-10s | %-14s |", who, ModelName(m));
    for (int q = 0; q < 2; ++q) {
      Cell all;
      double worst_graphs = 1.0, worst_descriptions = 1.0;
      for (const Table& t : blocks) {
        const Cell c = cell_of(t, q);
        all.rooms += c.rooms, all.graphs_right += c.graphs_right, all.descriptions += c.descriptions, all.right += c.right;
        worst_graphs = std::min(worst_graphs, c.GraphRate());
        worst_descriptions = std::min(worst_descriptions, c.DescriptionRate());
      }
      std::printf(" %4.2f / %5.3f (worst %4.2f / %5.3f)        |", all.GraphRate(), all.DescriptionRate(), worst_graphs,
                  worst_descriptions);
    }
    std::printf("\n");
  };
  for (int s = 0; s < 3; ++s) {
    for (const Model m : models) {
      line(SpeakerName(static_cast<Speaker>(s)), m, [&](const Table& t, int q) { return t.cells[static_cast<int>(m)][q][s]; });
    }
  }
  for (const Model m : models) {
    line("all", m, [&](const Table& t, int q) { return t.Over(m, q); });
    long right = 0, descriptions = 0;
    double worst = 1.0;
    for (const Table& t : blocks) {
      for (int q = 0; q < 2; ++q) right += t.Over(m, q).right, descriptions += t.Over(m, q).descriptions;
      worst = std::min(worst, t.DescriptionRate(m));
    }
    std::printf("%-10s | %-14s | descriptions right overall %5.3f (worst block %5.3f)\n", "all", ModelName(m),
                descriptions ? double(right) / double(descriptions) : 0.0, worst);
  }
}

}  // namespace

int main(int argc, char** argv) {
  int rooms = 30, blocks = 8;
  std::uint64_t seed = 1, held_out_from = 121;
  std::vector<Model> models = {Model::kThesis, Model::kIssue17, Model::kJoint};
  anchordb::engine::grounding::GroundingParams joint = JointOptions();
  bool failures = false;
  for (int i = 1; i + 1 < argc; i += 2) {
    const double x = std::atof(argv[i + 1]);
    if (std::strcmp(argv[i], "--rooms") == 0) rooms = std::atoi(argv[i + 1]);
    else if (std::strcmp(argv[i], "--seed") == 0) seed = std::strtoull(argv[i + 1], nullptr, 10);
    else if (std::strcmp(argv[i], "--blocks") == 0) blocks = std::max(1, std::atoi(argv[i + 1]));
    else if (std::strcmp(argv[i], "--held_out_from") == 0) held_out_from = std::strtoull(argv[i + 1], nullptr, 10);
    else if (std::strcmp(argv[i], "--slack") == 0) joint.joint.edge_fit_slack = x;
    else if (std::strcmp(argv[i], "--sight") == 0) joint.joint.line_of_sight_weight = x;
    else if (std::strcmp(argv[i], "--proximity_m") == 0) joint.joint.proximity_scale_m = x;
    else if (std::strcmp(argv[i], "--strength") == 0) joint.joint.frame_prior_strength = x;
    else if (std::strcmp(argv[i], "--noise") == 0) joint.joint.naming_noise = x;
    else if (std::strcmp(argv[i], "--repeat") == 0) joint.joint.repeat_weight = x;
    else if (std::strcmp(argv[i], "--margin") == 0) joint.ambiguity_margin = x;
    else if (std::strcmp(argv[i], "--floor") == 0) joint.category_floor = x;
    else if (std::strcmp(argv[i], "--failures") == 0) failures = std::atoi(argv[i + 1]) != 0;
    else if (std::strcmp(argv[i], "--models") == 0) {
      models.clear();
      const std::string list = argv[i + 1];
      if (list.find("thesis") != std::string::npos) models.push_back(Model::kThesis);
      if (list.find("issue17") != std::string::npos) models.push_back(Model::kIssue17);
      if (list.find("joint") != std::string::npos) models.push_back(Model::kJoint);
    } else {
      return std::fprintf(stderr, "unknown option %s\n", argv[i]), 2;
    }
  }
  const int total = rooms * blocks;
  if (failures) {  // every joint room whose graph ends wrong, traced
    for (int q = 0; q < 2; ++q) {
      for (int s = 0; s < 3; ++s) {
        for (int i = 0; i < total; ++i) {
          if (RunRoom(seed + static_cast<std::uint64_t>(i), static_cast<Speaker>(s), q, joint).graph_right) continue;
          std::fprintf(stderr, "room seed %llu, %s speaker, quality %c\n", static_cast<unsigned long long>(seed + i),
                       SpeakerName(static_cast<Speaker>(s)), "AB"[q]);
          TraceRoom(seed + static_cast<std::uint64_t>(i), static_cast<Speaker>(s), q, joint);
        }
      }
    }
    return 0;
  }
  std::printf("Adversarial grounding evaluation (issue 17): %d block(s) of %d rooms per speaker type, seeds %llu..%llu\n",
              blocks, rooms, static_cast<unsigned long long>(seed), static_cast<unsigned long long>(seed + total - 1));
  std::printf("joint model: slack %.2f, line of sight %.2f, proximity %.2f m, frame prior strength %.1f, naming noise %.3f, "
              "repeat weight %.2f, margin %.2f nats, floor %.2f\n", joint.joint.edge_fit_slack, joint.joint.line_of_sight_weight,
              joint.joint.proximity_scale_m, joint.joint.frame_prior_strength, joint.joint.naming_noise,
              joint.joint.repeat_weight, joint.ambiguity_margin, joint.category_floor);
  std::printf("cells: graphs all right / descriptions right\n");
  std::vector<Table> tables, looked_at, held_out;
  for (int b = 0; b < blocks; ++b) {
    const std::uint64_t first = seed + static_cast<std::uint64_t>(b) * static_cast<std::uint64_t>(rooms);
    tables.push_back(Evaluate(rooms, first, models, &joint));
    (first >= held_out_from ? held_out : looked_at).push_back(tables.back());
    std::printf("\nseeds %llu..%llu (%s)\n", static_cast<unsigned long long>(first), static_cast<unsigned long long>(first + rooms - 1),
                first >= held_out_from ? "held out" : "used for choices");
    PrintTable(tables.back(), models);
  }
  const auto pooled = [&](const std::vector<Table>& part, const char* what) {
    if (part.size() < 2) return;
    std::printf("\n%s: %zu blocks pooled (%zu rooms per speaker type), the worst block beside it\n", what, part.size(),
                part.size() * static_cast<std::size_t>(rooms));
    PrintPooled(part, models);
  };
  if (!looked_at.empty() && !held_out.empty()) {
    pooled(looked_at, "seeds used for choices");
    pooled(held_out, "held-out seeds");
  }
  pooled(tables, "all seeds");
  std::printf("(issue 17 bars: descriptions right >= 0.92 overall, A graphs 1.00, B graphs >= 0.85; thesis 91.9 %%)\n");
  return 0;
}
