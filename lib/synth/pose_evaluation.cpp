#include "toolinc/synth/pose_evaluation.hpp"

#include <atomic>
#include <thread>

#include "toolinc/core/error.hpp"

namespace toolinc {

namespace {

PoseCaseResult evaluate_case(const PoseEvaluationModel& model, int grasp, const PoseEvaluationConfig& config) {
  PoseCaseResult r;
  r.grasp = grasp;
  const PartialViewCase c = make_model_partial_view_case(model.cloud, model.symmetry,
                                                         config.seed * 1000003u + static_cast<std::uint32_t>(grasp),
                                                         any_grasp_range(), config.view);
  r.view_points = static_cast<int>(c.view.size());
  try {
    const PoseModel pose_model(c.model.points, config.align);
    const PoseResult result = align_pose(pose_model, c.view, config.align);
    r.errors = pose_errors(c, result.best.hand_from_model);
    r.pose_right =
        r.errors.rotation_deg <= config.max_rotation_deg && r.errors.translation_m <= config.max_translation_m;
    r.tooltip_right = r.errors.tooltip_m <= config.max_tooltip_m;
    r.right = r.pose_right || r.tooltip_right;
    r.ambiguous = result.ambiguous;
    r.feasible = result.feasibility.feasible;
  } catch (const MethodError& e) {
    r.failure = e.what();
  }
  return r;
}

}  // namespace

std::vector<PoseCaseResult> evaluate_poses(const std::vector<PoseEvaluationModel>& models,
                                           const PoseEvaluationConfig& config) {
  std::vector<PoseCaseResult> results(models.size() * static_cast<std::size_t>(config.grasps));
  // Each case is independent and writes only its own slot, so the results are the same for any jobs.
  std::atomic<std::size_t> next{0};
  const auto worker = [&] {
    for (std::size_t i; (i = next++) < results.size();) {
      const auto m = i / static_cast<std::size_t>(config.grasps);
      results[i] = evaluate_case(models[m], static_cast<int>(i % static_cast<std::size_t>(config.grasps)), config);
      results[i].model = static_cast<int>(m);
    }
  };
  std::vector<std::thread> threads;
  for (unsigned t = 1; t < config.jobs; ++t) threads.emplace_back(worker);
  worker();
  for (auto& thread : threads) thread.join();
  return results;
}

}  // namespace toolinc
