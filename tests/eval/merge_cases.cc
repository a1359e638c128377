// The runner of the multi-view merge cases: renders a case's script once, runs every requested merge strategy on
// the same frames with an injected camera pose error at every viewpoint, and scores the final movable layer against
// the renderer's object ids.
#include "tests/eval/merge_cases.h"

#include <algorithm>
#include <cmath>

#include "engine/scene/projection.h"
#include "engine/scene/scene_model.h"
#include "tests/eval/merge_case_scripts.h"
#include "tests/eval/object_geometry.h"
#include "tests/eval/pose_error.h"

namespace anchordb::eval {
namespace {

using Eigen::Isometry3d;
using Eigen::Vector3d;

using namespace geometry;      // NOLINT: the object geometry and the seeded pose errors are this file's vocabulary
using namespace pose_error;    // NOLINT
using namespace merge_script;  // NOLINT

// Relative pose of camera j in camera k.
Isometry3d Relative(const Isometry3d& X_k, const Isometry3d& X_j) { return X_k.inverse() * X_j; }

PoseErrorPair PoseErrors(const Isometry3d& true_rel, const Isometry3d& stored_rel,
                         const engine::MergeModelReport& report, const std::vector<Eigen::Vector3f>& points_j) {
  PoseErrorPair e;
  e.icp_converged = report.icp.converged;
  e.icp_applied = report.icp_applied;
  e.icp_fitness_m2 = report.icp.fitness_m2;
  const Isometry3d corrected = report.icp_applied ? report.icp.correction * stored_rel : stored_rel;
  const auto errors = [&](const Isometry3d& given, double& t, double& r, double& scene) {
    t = (given.translation() - true_rel.translation()).norm();
    r = RotationAngle(given.linear() * true_rel.linear().transpose());
    double sum = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < points_j.size(); i += 37) {
      const Vector3d p = points_j[i].cast<double>();
      sum += (given * p - true_rel * p).norm();
      ++n;
    }
    scene = n ? sum / n : 0.0;
  };
  errors(stored_rel, e.injected_translation_m, e.injected_rotation_rad, e.injected_scene_m);
  errors(corrected, e.translation_m, e.rotation_rad, e.scene_m);
  return e;
}

}  // namespace

const char* MergeStrategyName(engine::MergeStrategy s) {
  switch (s) {
    case engine::MergeStrategy::kAlgorithm2: return "merge";
    case engine::MergeStrategy::kNaive: return "naive";
    case engine::MergeStrategy::kNaiveWithoutIcp: return "naive w/o ICP";
  }
  return "?";
}

int StrategyIndex(engine::MergeStrategy s) {
  for (std::size_t i = 0; i < kMergeStrategies.size(); ++i) if (kMergeStrategies[i] == s) return static_cast<int>(i);
  return 0;
}

MergeCaseResult RunMergeCase(sim::Setting setting, MergeCase c, std::uint64_t seed, const MergeCaseOptions& options) {
  const PinholeIntrinsics K = sim::KinectIntrinsics();
  Script script = BuildScript(setting, c, seed, K);
  if (options.kind_sensor) {  // the sensor before issue 13 (sim::KindSensor()), keeping the case's range
    const sim::SensorModel kind = sim::KindSensor();
    script.sensor.correlated_noise_fraction = kind.correlated_noise_fraction;
    script.sensor.quantise_disparity = kind.quantise_disparity;
    script.sensor.lateral_jitter = kind.lateral_jitter;
    script.sensor.flying_pixels = kind.flying_pixels;
    script.sensor.speckle_dropouts = kind.speckle_dropouts;
  }
  const std::size_t n_phases = script.phases.size();

  // The pose stored with each viewpoint's model: a fresh localisation error at every viewpoint.
  Rng rng(Mix(seed, c, setting, 1));
  std::vector<Isometry3d> X_stored;
  for (const Phase& p : script.phases) {
    X_stored.push_back(
        WithPoseError(p.X_true, rng, options.pose_error_translation_m, options.pose_error_rotation_rad));
  }

  // Render every frame once; all strategies see the same frames.
  std::vector<std::vector<std::vector<std::uint16_t>>> depth(n_phases);
  std::vector<sim::Frame> last(n_phases);
  for (std::size_t p = 0; p < n_phases; ++p) {
    const Phase& ph = script.phases[p];
    const int frames = p + 1 < n_phases ? options.frames_a : 1 + options.frames_b;
    for (int i = 0; i < frames; ++i) {
      const sim::Scene& scene = ph.second && i >= frames / 2 ? *ph.second : ph.first;
      sim::Frame f = sim::Render(scene, K, ph.X_true, script.sensor, Mix(seed, c, setting, 1000 + 100 * p + i));
      depth[p].push_back(std::move(f.depth_mm));
      if (i + 1 == frames) {
        f.depth_mm = depth[p].back();
        last[p] = std::move(f);
      }
    }
  }

  MergeCaseResult result;
  result.description = script.description.str();
  const auto count = [&](int phase, int id) {
    const sim::Frame& f = last[static_cast<std::size_t>(phase)];
    std::size_t n = 0;
    for (std::size_t i = 0; i < f.object_id.size(); ++i) n += f.object_id[i] == id && f.depth_mm[i] != 0;
    return n;
  };
  for (const auto& hidden : script.hidden) {
    const int phase = hidden.first, id = hidden.second;  // named, not bound: clang 14 cannot capture a binding
    // An object hidden at a viewpoint where it is absent (added later) is checked in the scene where it is present.
    const sim::Scene& present = script.phases.back().Last();
    const sim::Scene& at = script.phases[static_cast<std::size_t>(phase)].Last();
    const bool in_scene = std::any_of(at.objects.begin(), at.objects.end(), [&](const auto& o) { return o.id == id; });
    if (in_scene) {
      result.hidden_pixels += count(phase, id);
    } else {
      const sim::Frame f = sim::Render(present, K, script.phases[static_cast<std::size_t>(phase)].X_true,
                                       script.sensor, 1);
      for (std::size_t i = 0; i < f.object_id.size(); ++i) result.hidden_pixels += f.object_id[i] == id && f.depth_mm[i];
    }
  }
  for (const auto& [phase, id] : script.shown) result.shown_pixels += count(phase, id);

  // Ground truth: the expected-movable objects' pixels with a measurement in the last frame.
  const sim::Frame& final_frame = last.back();
  std::vector<std::uint8_t> truth(final_frame.object_id.size(), 0);
  for (std::size_t i = 0; i < truth.size(); ++i) {
    for (int id : script.expected) truth[i] |= final_frame.object_id[i] == id && final_frame.depth_mm[i] != 0;
    result.truth_pixels += truth[i];
  }
  const auto zone = testing::TransitionZone(truth, K.width, K.height, options.zone_radius_px);
  // Truth pixels whose background (what the last viewpoint would see there without the expected-movable objects)
  // no earlier viewpoint measured: beyond its range, outside its view, hidden or dropped there.
  std::vector<std::uint8_t> unknown_background(truth.size(), 0);
  std::vector<std::uint8_t> within_theta(truth.size(), 0);  // the object within theta of its own background
  if (result.truth_pixels > 0) {
    sim::Scene empty = script.phases.back().Last();
    for (int id : script.expected) empty = Without(std::move(empty), id);
    const Isometry3d& X_last = script.phases.back().X_true;
    const sim::Frame behind = sim::Render(empty, K, X_last, Noiseless(), 7);
    for (std::size_t i = 0; i < truth.size(); ++i) {
      const double object = final_frame.true_depth_m[i], back = behind.true_depth_m[i];
      within_theta[i] = truth[i] && back > 0.0 && back - object < options.beta * object;
    }
    sim::SensorModel exact = script.sensor;
    exact.noise = false;
    std::vector<std::pair<std::size_t, sim::Frame>> earlier;  // (phase, its view before and after a change)
    for (std::size_t p = 0; p + 1 < n_phases; ++p) {
      earlier.push_back({p, sim::Render(script.phases[p].first, K, script.phases[p].X_true, exact, 7)});
      if (script.phases[p].second) {
        earlier.push_back({p, sim::Render(*script.phases[p].second, K, script.phases[p].X_true, exact, 7)});
      }
    }
    for (int v = 0; v < K.height; ++v) {
      for (int u = 0; u < K.width; ++u) {
        const std::size_t i = static_cast<std::size_t>(v) * K.width + u;
        if (!truth[i] || zone[i]) continue;
        const double z = behind.true_depth_m[i];
        bool known = false;
        if (z > 0.0) {
          const Vector3d P = X_last * Vector3d((u - K.cx) / K.fx * z, (v - K.cy) / K.fy * z, z);
          for (std::size_t e = 0; e < earlier.size() && !known; ++e) {
            const auto& [p, f] = earlier[e];
            const Vector3d q = script.phases[p].X_true.inverse() * P;
            if (q.z() <= 0.05) continue;
            const double pu = K.fx * q.x() / q.z() + K.cx, pv = K.fy * q.y() / q.z() + K.cy;
            if (pu < 0 || pv < 0 || pu >= K.width || pv >= K.height) continue;
            const std::size_t j = static_cast<std::size_t>(pv) * K.width + static_cast<std::size_t>(pu);
            known = f.depth_mm[j] != 0 && std::abs(f.true_depth_m[j] - q.z()) < 0.02 + 0.01 * q.z();
          }
        }
        unknown_background[i] = !known;
        result.unknown_background_pixels += !known;
      }
    }
  }

  engine::SceneModelParams scene_params;
  scene_params.beta = options.beta;
  for (const engine::MergeStrategy strategy : options.strategies) {
    StrategyResult& out = result.by_strategy[static_cast<std::size_t>(StrategyIndex(strategy))];
    engine::MergeParams merge_params;
    merge_params.strategy = strategy;
    merge_params.beta = options.beta;
    merge_params.pose_sigma_factor = options.pose_sigma_factor;
    merge_params.frustum_far_m = script.frustum_far_m;
    merge_params.record_decisions = strategy == engine::MergeStrategy::kAlgorithm2;
    std::vector<std::uint8_t> decision(truth.size(), 0);  // at the last viewpoint (see StrategyResult)
    std::vector<engine::SceneModelState> models;
    for (std::size_t p = 0; p < n_phases; ++p) {
      engine::SceneModelState state = engine::NewSceneModel(K.width, K.height);
      std::size_t first = 0;
      if (p > 0) {
        std::vector<engine::PriorModel> priors;
        for (std::size_t j = 0; j < p; ++j) {
          priors.push_back({static_cast<std::int64_t>(j + 1), K, X_stored[j], models[j].background_m});
        }
        const engine::MergeResult merged = engine::MergeAndApplyFirstFrame(
            state, depth[p][0], 1000.0, {}, scene_params, K, X_stored[p], priors, merge_params);
        out.timing.icp_ms += merged.timing.icp_ms;
        out.timing.rasterise_ms += merged.timing.rasterise_ms;
        out.timing.merge_ms += merged.timing.merge_ms;
        for (std::size_t j = 0; j < merged.models.size(); ++j) {
          if (p + 1 == n_phases && !merged.models[j].decisions.empty()) {
            for (std::size_t i = 0; i < decision.size(); ++i) {
              const auto d = static_cast<engine::MergeDecision>(decision[i]);
              if (d != engine::MergeDecision::kReplacedFarther && d != engine::MergeDecision::kRearProjected) {
                decision[i] = merged.models[j].decisions[i];
              }
            }
          }
          out.reports.push_back(merged.models[j]);
          out.reports.back().decisions.clear();
          if (strategy == engine::MergeStrategy::kNaiveWithoutIcp) continue;
          const std::vector<Eigen::Vector3f> points_j =
              engine::BackProject(models[j].background_m, K, Isometry3d::Identity());
          out.icp.push_back(PoseErrors(Relative(script.phases[p].X_true, script.phases[j].X_true),
                                       Relative(X_stored[p], X_stored[j]), merged.models[j], points_j));
        }
        first = 1;
      }
      for (std::size_t i = first; i < depth[p].size(); ++i) {
        engine::ApplyFrame(state, depth[p][i], 1000.0, {}, scene_params);
      }
      models.push_back(std::move(state));
    }
    const engine::SceneModelState& final_model = models.back();
    const auto cleaned = engine::CleanMovable(final_model.movable, K.width, K.height);
    out.raw = testing::CountPixels(final_model.movable, truth, {});
    out.cleaned = testing::CountPixels(cleaned, truth, {});
    out.cleaned_zone = testing::CountPixels(cleaned, truth, zone);
    for (std::size_t i = 0; i < cleaned.size(); ++i) out.unknown_background_detected += unknown_background[i] && cleaned[i];
    if (strategy == engine::MergeStrategy::kAlgorithm2) {
      for (std::size_t i = 0; i < cleaned.size(); ++i) {
        if (!truth[i] || zone[i] || cleaned[i]) continue;
        if (within_theta[i]) ++out.fn_within_theta;
        else if (unknown_background[i]) ++out.fn_unknown_background, ++out.fn_unknown_by_decision[decision[i]];
        else if (final_model.movable[i]) ++out.fn_cleaned_away;
        else ++out.fn_by_decision[decision[i]];
      }
    }
  }
  return result;
}

}  // namespace anchordb::eval
