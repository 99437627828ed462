// Accuracy of estimate-frame and find-tooltip against ground truth (issue: foundation and the tool
// frame). Tolerances: noise sigma 1.5 mm per coordinate on thousands of points leaves the handle fit's
// angle error well under a degree, so 3 degrees bounds the method's bias, not the noise; the tooltip is
// one surface point, whose noise (about 3 sigma along the effector axis at the front) is ~5 mm, hence
// 10 mm in 97% of cases and never beyond 20 mm.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "support/synthetic_cases.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/core/random.hpp"
#include "toolinc/core/rigid.hpp"
#include "toolinc/frame/tool_frame.hpp"
#include "toolinc/frame/tooltip.hpp"
#include "toolinc/results/results_json.hpp"
#include "toolinc/synth/evaluation.hpp"

using namespace toolinc;
using toolinc::testing::HeldToolCase;
using toolinc::testing::make_held_tool;

namespace {

constexpr int kGraspsPerFamily = 24;

// The two ways to the frame: the accuracy floors hold for both; the rules' own tied and rival planes and
// side doubt are tested on the rules.
constexpr FrameMethod kMethods[] = {FrameMethod::rules, FrameMethod::search};
ToolFrameConfig with_method(FrameMethod method) {
  ToolFrameConfig config;
  config.method = method;
  return config;
}
const ToolFrameConfig kRules = with_method(FrameMethod::rules);

// A family's tool held with the seed's grasp and evaluated as evaluate-models does (6 cm hand cut,
// sigma 1.5 mm); the noise's seed is the grasp's index.
std::pair<toolinc::testing::HeldToolCase, HeldToolErrors> evaluate_grasp(ToolFamily family, std::uint32_t seed, int g,
                                                                         FrameMethod method) {
  auto held = make_held_tool(family, seed);
  Rng noise(static_cast<std::uint32_t>(g));
  const HeldToolErrors e = evaluate_held_tool(held.model.points, symmetry_of(family), truth_tip_of(family), held.grasp,
                                              0.06, 0.0015, noise, with_method(method));
  return {std::move(held), e};
}

struct FamilyStats {
  int cases = 0, tips_within_10mm = 0;
  double worst_handle_deg = 0.0, worst_tip = 0.0;
};

}  // namespace

// Either method: the handle within 3 degrees in 97 % of cases and never beyond 5 (the search's trimmed
// lines, fitted to no surface, may lean a little more than the rules' cylinder fits); the effector side
// right wherever it is salient; the tooltip within 10 mm in 97 % and never beyond 25 mm: a scoop's far end
// ties its rim's corner with the middle of its far edge within the noise (the truth takes whichever of
// the model's samples lies farthest, the rule the rim), and they lie a scoop's depth apart (2 cm, 2.3 with
// the families' variation).
TEST(ToolFrameAccuracy, EveryFamilyManyGrasps) {
  for (const FrameMethod method : kMethods) {
    SCOPED_TRACE(to_string(method));
    std::map<std::string, FamilyStats> stats;
    int cases = 0, within_10mm = 0, handle_within_3deg = 0;
    for (ToolFamily family : all_families()) {
      for (int g = 0; g < kGraspsPerFamily; ++g) {
        SCOPED_TRACE(to_string(family) + " grasp " + std::to_string(g));
        const auto [held, e] = evaluate_grasp(family, 1000u + static_cast<std::uint32_t>(g), g, method);
        ASSERT_TRUE(e.failure.empty()) << e.failure;
        EXPECT_TRUE(e.right_handed);
        EXPECT_LE(e.handle_axis_deg, 5.0);
        if (has_salient_effector(family)) EXPECT_TRUE(e.effector_sign_right);
        EXPECT_LE(e.tooltip_m, 0.025);
        auto& s = stats[to_string(family)];
        ++s.cases;
        s.worst_handle_deg = std::max(s.worst_handle_deg, e.handle_axis_deg);
        s.worst_tip = std::max(s.worst_tip, e.tooltip_m);
        if (e.tooltip_m <= 0.010) ++s.tips_within_10mm, ++within_10mm;
        handle_within_3deg += e.handle_axis_deg <= 3.0;
        ++cases;
      }
    }
    for (const auto& [name, s] : stats)
      std::printf("%-6s %-9s cases %3d  worst handle %.2f deg  worst tooltip %.1f mm  within 10 mm %d\n",
                  to_string(method).c_str(), name.c_str(), s.cases, s.worst_handle_deg, 1000 * s.worst_tip,
                  s.tips_within_10mm);
    EXPECT_GE(within_10mm, static_cast<int>(0.97 * cases)) << within_10mm << " of " << cases;
    EXPECT_GE(handle_within_3deg, static_cast<int>(0.97 * cases)) << handle_within_3deg << " of " << cases;
  }
}

// Shapes of real tools the regression families never had: a flat spatula (its symmetry plane is across
// the blade, its tip the blade's far end), a square plate and a four-armed star (any of four tips). The
// same noise and hand cut; the floors are the real-tools issue's: tooltip within 10 mm and handle axis
// within 3 degrees in 95 % of cases.
TEST(ToolFrameAccuracy, RealShapesManyGrasps) {
  for (const FrameMethod method : kMethods) {
    SCOPED_TRACE(to_string(method));
    int cases = 0, within_10mm = 0, handle_within_3deg = 0, blade_planes_right = 0, blades = 0;
    for (ToolFamily family : real_shape_families()) {
      for (int g = 0; g < kGraspsPerFamily; ++g) {
        SCOPED_TRACE(to_string(family) + " grasp " + std::to_string(g));
        const auto [held, e] = evaluate_grasp(family, 2000u + static_cast<std::uint32_t>(g), g, method);
        ASSERT_TRUE(e.failure.empty()) << e.failure;
        EXPECT_TRUE(e.right_handed);
        within_10mm += e.tooltip_m <= 0.010;
        handle_within_3deg += e.handle_axis_deg <= 3.0;
        ++cases;
        if (family == ToolFamily::blade) {  // the plane across the blade: canonical Z, not the blade's own
          const ToolFrame frame = estimate_tool_frame(held.observed, with_method(method));
          ++blades;
          blade_planes_right +=
              frame.diagnostics.head_is_blade &&
              std::abs(frame.symmetry_axis().dot(held.grasp.topLeftCorner<3, 3>().col(2))) >= std::cos(10 * M_PI / 180);
        }
      }
    }
    std::printf(
        "%s, real shapes: %d of %d tooltips within 10 mm, %d handle axes within 3 deg, %d of %d blades' planes "
        "across the blade\n",
        to_string(method).c_str(), within_10mm, cases, handle_within_3deg, blade_planes_right, blades);
    EXPECT_GE(within_10mm, static_cast<int>(0.95 * cases)) << within_10mm << " of " << cases;
    EXPECT_GE(handle_within_3deg, static_cast<int>(0.95 * cases)) << handle_within_3deg << " of " << cases;
    EXPECT_GE(blade_planes_right, static_cast<int>(0.95 * blades)) << blade_planes_right << " of " << blades;
  }
}

// A real scoop's belly often bulges behind its handle's axis (the lab's SHO1), so it reaches farther
// backwards than forwards; its edges still curl towards its working, concave side. The generated
// shovel, and the same with its blade lowered by the scoop's depth (belly behind the handle), must
// both face +X, and their tips be right: within 10 mm in 95 % of grasps. The search's handle candidates
// include lines the belly tilts (the whole tool's principal line leans towards it by 4-14 degrees), which
// it sometimes keeps: on the lowered scoop its tips are held to 15 mm in 95 % (the known gap, method.md).
TEST(ToolFrameAccuracy, ScoopsFaceTheirConcaveSideWhereverTheirBellyReaches) {
  for (const FrameMethod method : kMethods)
    for (const double lowered : {0.0, 0.02}) {
      const double tolerance = method == FrameMethod::search && lowered > 0.0 ? 0.015 : 0.010;
      int sign_right = 0, within_tolerance = 0;
      for (int g = 0; g < kGraspsPerFamily; ++g) {
        SCOPED_TRACE(to_string(method) + ", blade lowered " + std::to_string(lowered) + " grasp " + std::to_string(g));
        auto held = make_held_tool(ToolFamily::shovel, 3000u + static_cast<std::uint32_t>(g));
        Points scoop = held.model.points;
        for (auto& p : scoop)
          if (p.y() < -held.shape.handle_length) p.x() -= lowered;
        Rng noise(static_cast<std::uint32_t>(g));
        const HeldToolErrors e = evaluate_held_tool(scoop, ToolSymmetry::mirror, TruthTip::far_end, held.grasp, 0.06,
                                                    0.0015, noise, with_method(method));
        ASSERT_TRUE(e.failure.empty()) << e.failure;
        sign_right += e.effector_sign_right;
        within_tolerance += e.tooltip_m <= tolerance;
      }
      std::printf("%s, scoop lowered by %.0f mm: effector sign right %d of %d, tooltips within %.0f mm %d\n",
                  to_string(method).c_str(), 1000 * lowered, sign_right, kGraspsPerFamily, 1000 * tolerance,
                  within_tolerance);
      EXPECT_GE(sign_right, kGraspsPerFamily - 1) << to_string(method) << ", lowered " << lowered;
      EXPECT_GE(within_tolerance, static_cast<int>(0.95 * kGraspsPerFamily))
          << to_string(method) << ", lowered " << lowered;
    }
}

// Grasp g of the generated sticks from `first_seed`, its model reshaped by reshape(points, far_y) (far_y:
// its far end's, negative) and seen in the hand with the stereo's noise.
struct ReshapedStick {
  HeldToolCase held;
  Points shape, observed;
};
template <class Reshape>
ReshapedStick reshaped_stick(std::uint32_t first_seed, int g, Reshape reshape) {
  ReshapedStick stick{make_held_tool(ToolFamily::stick, first_seed + static_cast<std::uint32_t>(g)), {}, {}};
  double far_y = 0.0;
  for (const auto& p : stick.held.model.points) far_y = std::min(far_y, p.y());
  stick.shape = reshape(stick.held.model.points, far_y);
  Rng noise(static_cast<std::uint32_t>(g));
  stick.observed = observe_in_hand(stick.shape, stick.held.grasp, 0.06, 0.0015, noise);
  return stick;
}

// A bent stick has no head: its effector axis is arbitrary, so a bump along its shaft must not be
// taken for the tip. The generated stick bowed sideways by up to 6 mm (a sine arch, straight at both
// ends): its handle along its chord, its tip at its far end (any turn about the handle counts, as for a
// round stick). The rules must also read it as a stick, since they decide its head from that; the search
// weighs the frames about each handle instead.
TEST(ToolFrameAccuracy, BentSticksTakeTheirFarEnd) {
  for (const FrameMethod method : kMethods) {
    int sticks = 0, within_10mm = 0, handle_within_3deg = 0;
    for (int g = 0; g < kGraspsPerFamily; ++g) {
      SCOPED_TRACE(to_string(method) + ", grasp " + std::to_string(g));
      const ReshapedStick bent = reshaped_stick(4000u, g, [](Points points, double far_y) {
        for (auto& p : points) p.x() += 0.006 * std::sin(M_PI * p.y() / far_y);
        return points;
      });
      const ToolGroundTruth truth =
          tool_ground_truth(bent.shape, ToolSymmetry::axial, TruthTip::weighted, bent.held.grasp);
      const ToolFrame frame = estimate_tool_frame(bent.observed, with_method(method));
      const Tooltip tip = find_tooltip(bent.observed, frame);
      sticks += frame.stick;
      within_10mm += tooltip_error(truth, tip.position) <= 0.010;
      handle_within_3deg += handle_axis_error_deg(truth, frame.handle_axis()) <= 3.0;
    }
    std::printf("%s, bent sticks: %d of %d taken for sticks, %d tooltips within 10 mm, %d handle axes within 3 deg\n",
                to_string(method).c_str(), sticks, kGraspsPerFamily, within_10mm, handle_within_3deg);
    if (method == FrameMethod::rules) EXPECT_EQ(sticks, kGraspsPerFamily);
    EXPECT_GE(within_10mm, static_cast<int>(0.95 * kGraspsPerFamily)) << to_string(method);
    EXPECT_GE(handle_within_3deg, static_cast<int>(0.95 * kGraspsPerFamily)) << to_string(method);
  }
}

// A reconstruction leaves a fringe beyond a surface's edge: a view merged a few degrees off its true pose
// adds a second far end beside the stick's own (the robot's reconstructions reach a median 10.5 mm beyond
// the true tip, 17 mm at the 90th percentile). The generated stick with its far quarter seen again 12 mm
// to one side at its end (turned about the hand) is still a stick, whose tip is its far end (any turn
// about the handle counts). At a stick-width of 2 cm the search took 11 of 24 for heads, 6 tips beyond
// 10 mm. A stick standing out beyond a clean stick's width may as well be bent: never confident.
TEST(ToolFrameAccuracy, SmearedSticksTakeTheirFarEnd) {
  const ToolFrameConfig defaults;
  for (const FrameMethod method : kMethods) {
    int sticks = 0, within_10mm = 0, fringed = 0;
    for (int g = 0; g < kGraspsPerFamily; ++g) {
      SCOPED_TRACE(to_string(method) + ", grasp " + std::to_string(g));
      const ReshapedStick smeared = reshaped_stick(4100u, g, [](const Points& points, double far_y) {
        const Eigen::Matrix3d turn = Eigen::AngleAxisd(0.012 / -far_y, Vec3::UnitZ()).toRotationMatrix();
        Points out = points;
        for (const auto& p : points)
          if (p.y() < 0.75 * far_y) out.push_back(turn * p);
        return out;
      });
      const ToolFrame frame = estimate_tool_frame(smeared.observed, with_method(method));
      const Tooltip tip = find_tooltip(smeared.observed, frame);
      sticks += frame.stick;
      within_10mm += tooltip_error(smeared.held.truth, tip.position) <= 0.010;
      if (frame.stick && frame.diagnostics.head_extent > defaults.clean_stick_width) {
        ++fringed;
        EXPECT_FALSE(tip.confidence.confident) << "stands out " << frame.diagnostics.head_extent << " m";
      }
    }
    std::printf(
        "%s, smeared sticks: %d of %d taken for sticks (%d standing out beyond a clean stick's width), %d "
        "tooltips within 10 mm\n",
        to_string(method).c_str(), sticks, kGraspsPerFamily, fringed, within_10mm);
    if (method == FrameMethod::rules) EXPECT_GE(sticks, static_cast<int>(0.95 * kGraspsPerFamily));
    EXPECT_GE(within_10mm, static_cast<int>(0.95 * kGraspsPerFamily)) << to_string(method);
  }
}

TEST(ToolFrameAccuracy, TiedSymmetryPlanesAreReportedWithTheirTips) {
  // The rules: a T mirrors across the plane along its bar and the one across it: the tooltip names the
  // other plane's tip (the bar's side, half a bar away) and says the choice was the rule's. A hook mirrors
  // across its own plane only. (The search weighs such planes as hypotheses of their own.)
  const auto t_bar = make_held_tool(ToolFamily::t_bar, 5);
  const Tooltip t = find_tooltip(t_bar.observed, estimate_tool_frame(t_bar.observed, kRules));
  const auto plane = std::find_if(t.alternatives.begin(), t.alternatives.end(),
                                  [](const TooltipAlternative& a) { return a.source == "tied symmetry plane"; });
  ASSERT_NE(plane, t.alternatives.end());
  EXPECT_GT((plane->position - t.position).norm(), 0.03);
  EXPECT_TRUE(t.ambiguous);
  const auto hook = make_held_tool(ToolFamily::hook, 5);
  const ToolFrame hook_frame = estimate_tool_frame(hook.observed, kRules);
  EXPECT_EQ(hook_frame.tied_planes.size(), 1u);
  const Tooltip h = find_tooltip(hook.observed, hook_frame);
  EXPECT_FALSE(h.ambiguous);
  // The uncertainty is of the order of the noise, not of the tool.
  EXPECT_GT(h.uncertainty_m, 0.0);
  EXPECT_LT(h.uncertainty_m, 0.01);
  EXPECT_GT(h.noise_m, 0.0005);
  EXPECT_LT(h.noise_m, 0.003);
}

TEST(ToolFrameAccuracy, FourfoldTruthHasFourTips) {
  const auto held = make_held_tool(ToolFamily::square_plate, 9);
  ASSERT_EQ(held.truth.tooltips.size(), 4u);
  for (std::size_t k = 1; k < 4; ++k) {  // a quarter turn apart about the handle, at the same height
    const Vec3 a =
        held.grasp.topLeftCorner<3, 3>().transpose() * (held.truth.tooltips[k - 1] - held.grasp.topRightCorner<3, 1>());
    const Vec3 b =
        held.grasp.topLeftCorner<3, 3>().transpose() * (held.truth.tooltips[k] - held.grasp.topRightCorner<3, 1>());
    EXPECT_NEAR(a.y(), b.y(), 1e-9);
    EXPECT_NEAR(Vec3(a.x(), 0, a.z()).dot(Vec3(b.x(), 0, b.z())), 0.0, 1e-9);
  }
}

TEST(ToolFrameAccuracy, SalientEffectorIsDetectedWhereItExists) {
  for (ToolFamily family : all_families()) {
    const auto held = make_held_tool(family, 77);
    EXPECT_EQ(estimate_tool_frame(held.observed).diagnostics.salient_effector, has_salient_effector(family))
        << to_string(family);
  }
}

TEST(ToolFrameAccuracy, MeasuredSymmetryMatchesTheFamilies) {
  for (auto families : {all_families(), real_shape_families()})
    for (ToolFamily family : families)
      EXPECT_EQ(measure_symmetry(generate_tool(default_shape(family), 1).points), symmetry_of(family))
          << to_string(family);
}

TEST(ToolFrameAccuracy, FrameIsRightHandedAndDeterministic) {
  const auto held = make_held_tool(ToolFamily::hook, 7);
  const ToolFrame a = estimate_tool_frame(held.observed);
  const ToolFrame b = estimate_tool_frame(held.observed);
  EXPECT_EQ(a.axes, b.axes);
  EXPECT_EQ(a.origin, b.origin);
  EXPECT_NEAR(a.axes.determinant(), 1.0, 1e-12);
}

TEST(ToolFrameAccuracy, StickTooltipIsAtTheFarEndNotMidShaft) {
  // The original's mid-plane bug put a stick's tooltip mid-shaft; here the across-handle plane is
  // never eligible, so the tooltip must be near the far end for every grasp.
  for (int g = 0; g < 10; ++g) {
    const auto held = make_held_tool(ToolFamily::stick, 50u + g);
    const ToolFrame frame = estimate_tool_frame(held.observed);
    const Tooltip tip = find_tooltip(held.observed, frame);
    const Vec3 in_canonical =
        held.grasp.topLeftCorner<3, 3>().transpose() * (tip.position - held.grasp.topRightCorner<3, 1>());
    const double length = held.shape.handle_length + held.shape.head_height;
    EXPECT_NEAR(in_canonical.y(), -length, 0.01) << "grasp " << g;
  }
}

TEST(ToolFrameAccuracy, WeightedRuleUsesItsWeight) {
  // With weight 1 the weighted rule is pure "in front of the effector plane"; with weight 0 it is pure
  // distance from the hand: the two must pick different points on a hoe, and weight 0 the farthest one.
  const auto held = make_held_tool(ToolFamily::hoe, 3);
  const ToolFrame frame = estimate_tool_frame(held.observed);
  TooltipConfig front_only, distance_only;
  front_only.rule = distance_only.rule = TooltipRule::weighted;
  front_only.effector_weight = 1.0;
  distance_only.effector_weight = 0.0;
  const Tooltip a = find_tooltip(held.observed, frame, front_only);
  const Tooltip b = find_tooltip(held.observed, frame, distance_only);
  EXPECT_GT((a.surface_point - b.surface_point).norm(), 0.005);
  double farthest = 0.0;
  for (const auto& p : held.observed) farthest = std::max(farthest, p.norm());
  EXPECT_NEAR(b.surface_point.norm(), farthest, 0.005);
}

TEST(ToolFrameAccuracy, IsolatedOutlierIsNeverTheTooltip) {
  auto held = make_held_tool(ToolFamily::hoe, 11);
  const ToolFrame frame = estimate_tool_frame(held.observed);
  const Tooltip clean = find_tooltip(held.observed, frame);
  const Vec3 outlier = clean.position + 0.05 * frame.effector_axis();
  held.observed.push_back(outlier);
  // 5 cm off the tool it is joined to it (piece-gap), and the density check rejects it.
  const Tooltip with_outlier = find_tooltip(held.observed, frame);
  EXPECT_LT((with_outlier.position - clean.position).norm(), 1e-9);
  EXPECT_GE(with_outlier.rejected_sparse, 1);
  // 20 cm off it is a piece of its own: not the tool.
  held.observed.back() = clean.position + 0.2 * frame.effector_axis();
  const Tooltip far = find_tooltip(held.observed, frame);
  EXPECT_LT((far.position - clean.position).norm(), 1e-9);
  EXPECT_EQ(far.detached_points, 1);
}

TEST(ToolFrameAccuracy, HandleThickerThanTheHandHoldsIsDoubtful) {
  // Either method: the same hoe with its handle 1 cm and 3 cm in radius: the thin one raises no handle
  // doubt, the thick one is doubtful because of it.
  for (const FrameMethod method : kMethods)
    for (const double radius : {0.01, 0.03}) {
      ToolShape shape = default_shape(ToolFamily::hoe);
      shape.handle_radius = radius;
      Rng rng(5);
      const Points observed = observe_in_hand(generate_tool(shape, 5).points, random_grasp({}, rng), 0.06, 0.0015, rng);
      const ToolFrame frame = estimate_tool_frame(observed, with_method(method));
      const bool doubted =
          std::any_of(frame.confidence.doubts.begin(), frame.confidence.doubts.end(),
                      [](const std::string& d) { return d.find("grasp-max-radius") != std::string::npos; });
      EXPECT_EQ(doubted, radius > ToolFrameConfig{}.grasp_max_radius)
          << to_string(method) << ", " << radius << " m, fitted " << frame.handle_radius;
      if (doubted) EXPECT_FALSE(frame.confidence.confident);
    }
}

TEST(ToolFrameDegenerate, ReasonsAreGiven) {
  const auto expect_method_error = [](const Points& points, const std::string& word) {
    try {
      estimate_tool_frame(points);
      ADD_FAILURE() << "expected a MethodError mentioning " << word;
    } catch (const MethodError& e) {
      EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
    }
  };
  expect_method_error({Vec3(0.1, -0.1, 0), Vec3(0.1, -0.11, 0), Vec3(0.1, -0.12, 0)}, "too few");
  Points line, plane, inside;
  for (int i = 0; i < 500; ++i) {
    line.emplace_back(0.1, -0.1 - 0.0004 * i, 0.0);
    plane.emplace_back(0.1 + 0.0005 * (i % 25), -0.1 - 0.004 * (i / 25), 0.0);
    inside.emplace_back(0.01, -0.0001 * i, 0.0);
  }
  expect_method_error(line, "collinear");
  expect_method_error(plane, "planar");
  expect_method_error(inside, "hand radius");
}

TEST(ToolFrameDegenerate, HandSkipMustLeaveAHandle) {
  ToolFrameConfig config;
  config.handle_hand_skip = config.handle_fraction;
  EXPECT_THROW(estimate_tool_frame(make_held_tool(ToolFamily::hook, 3).observed, config), std::invalid_argument);
}

// The rules: a hoe's head mirrors across one plane only; a flat top's square plate across two at right
// angles: the other is its rival, and find-tooltip reports the rival's tip.
TEST(ToolFrameAccuracy, RivalSymmetryPlanesAreTheOtherMirrorsOfTheHead) {
  for (int g = 0; g < 4; ++g) {
    const auto hoe = make_held_tool(ToolFamily::hoe, 60u + g);
    EXPECT_TRUE(estimate_tool_frame(hoe.observed, kRules).rival_planes.empty()) << "hoe grasp " << g;
    const auto plate = make_held_tool(ToolFamily::flat_top, 60u + g);
    const ToolFrame frame = estimate_tool_frame(plate.observed, kRules);
    ASSERT_FALSE(frame.rival_planes.empty()) << "flat top grasp " << g;
    for (const auto& rival : frame.rival_planes) {
      EXPECT_LT(std::abs(rival.normal.dot(frame.symmetry_axis())), std::cos(M_PI / 6));
      EXPECT_LE(rival.score, frame.symmetry_score + ToolFrameConfig{}.symmetry_doubt_margin);
    }
    const Tooltip tip = find_tooltip(plate.observed, frame);
    EXPECT_TRUE(std::any_of(tip.alternatives.begin(), tip.alternatives.end(),
                            [](const TooltipAlternative& a) {
                              return a.source == "rival symmetry plane" || a.source == "tied symmetry plane";
                            }))
        << "flat top grasp " << g;
  }
}

namespace {

// A flat plate -depth <= x <= 0 sampled every millimetre, its edge at x = 0, and beyond it a fringe `fringe`
// deep whose density falls linearly to nothing (a fattened silhouette); `outermost` is its outermost point.
Points plate_with_fringe(double fringe, Vec3& outermost, double depth = 0.05) {
  Rng rng(5);
  Points plate;
  for (double y = -0.03; y <= 0.03; y += 0.001)
    for (double x = -depth; x <= fringe + 1e-9; x += 0.001)
      if (x <= 1e-9 || rng.uniform() > x / fringe) plate.push_back(Vec3(x, y, 0.0));
  outermost = plate.front();
  for (const auto& p : plate)
    if (p.x() > outermost.x()) outermost = p;
  return plate;
}

}  // namespace

// The tip is moved off a fringe towards the surface's edge, and not moved at a sharp edge or off a thin
// part's side.
TEST(TooltipEdge, FringeRetreatsTowardsTheEdgeSharpEdgesAndThinPartsStay) {
  const TooltipConfig config;
  Vec3 outermost;
  const Points fringed = plate_with_fringe(0.008, outermost);
  const double back = edge_retreat(KdTree(fringed), outermost, Vec3::UnitX(), config);
  // The point ends within 4 mm of the true edge (half density lies inside the fringe's ramp), from
  // about 8 mm out.
  EXPECT_GT(outermost.x(), 0.006);
  EXPECT_LT(std::abs(outermost.x() - back), 0.004) << "outermost at " << outermost.x() << ", back " << back;

  // A face's shell seen from outside (two rows, hollow behind: a hook's or a cap's front) with the same
  // fringe: the density peaks at the shell, and the point goes back towards it though nothing lies behind
  // (the density fringe-depth behind lies in the hollow: against it the point would stay). The fringe holds more
  // points than the shell, so half the peak lies well out in the fringe's ramp: 2 of its 7 mm.
  const Points shell = plate_with_fringe(0.008, outermost, 0.001);
  EXPECT_GE(edge_retreat(KdTree(shell), outermost, Vec3::UnitX(), config), 0.0015);

  const Points sharp = plate_with_fringe(0.0, outermost);
  EXPECT_LE(edge_retreat(KdTree(sharp), outermost, Vec3::UnitX(), config), 0.001);

  // A thin rod (radius 1.5 mm) seen across: from its front side, 1 cm back lies nothing denser.
  Points rod;
  for (double y = -0.05; y <= 0.05; y += 0.0005)
    for (int k = 0; k < 8; ++k)
      rod.push_back(Vec3(0.0015 * std::cos(k * M_PI / 4), y, 0.0015 * std::sin(k * M_PI / 4)));
  EXPECT_LE(edge_retreat(KdTree(rod), Vec3(0.0015, 0, 0), Vec3::UnitX(), config), 0.001);

  TooltipConfig off = config;
  off.fringe_depth = 0.0;
  plate_with_fringe(0.008, outermost);
  EXPECT_EQ(edge_retreat(KdTree(fringed), outermost, Vec3::UnitX(), off), 0.0);
}

// A fringe need not run the way the rule's score grows: smear below a head's edge (a rake's teeth, a hoe's
// blade seen edge-on) runs along the handle, and the weighted rule, which also likes distance from the hand,
// takes its lower end in front. Here a bar 1 cm tall ends at x = 6 cm, and below its front half hangs a
// smear 15 mm deep, at most 0.4 of the bar's density and thinning downwards (the robot's reconstructions
// are smeared so). Back along the rule's gradient (mostly along x) the way stays in the smear and the tip
// 9-14 mm below the corner; back towards the surface's mass it reaches the bar's edge, a few millimetres
// in from the corner where the corner's quarter density reaches half the bar's.
TEST(TooltipEdge, SmearBelowAHeadRetreatsTowardsTheHeadNotAlongTheRule) {
  const double front = 0.06, bottom = -0.26, smear = 0.015;
  for (std::uint32_t seed = 1; seed <= 8; ++seed) {
    Rng rng(seed);
    Points tool;
    for (double y = -0.07; y >= -0.25; y -= 0.001) tool.push_back(Vec3(0.0, y, 0.0));
    for (double x = -0.04; x <= front + 1e-9; x += 0.001)
      for (double y = bottom; y <= bottom + 0.01 + 1e-9; y += 0.001)
        for (double z = -0.006; z <= 0.006 + 1e-9; z += 0.004)
          tool.push_back(Vec3(x + rng.uniform(-0.0005, 0.0005), y + rng.uniform(-0.0005, 0.0005), z));
    for (double x = 0.02; x <= front + 1e-9; x += 0.001)
      for (double y = bottom - 0.001; y >= bottom - smear; y -= 0.001)
        for (double z = -0.006; z <= 0.006 + 1e-9; z += 0.004)
          if (rng.uniform() < 0.4 * (1.0 - (bottom - y) / smear))
            tool.push_back(Vec3(x + rng.uniform(-0.0005, 0.0005), y, z));
    ToolFrame frame;
    frame.origin = Vec3(0.0, -0.2, 0.0);
    frame.handle_point = Vec3(0.0, -0.1, 0.0);
    const Tooltip tip = find_tooltip(tool, frame);
    EXPECT_LT(tip.surface_point.y(), bottom - 0.008) << "seed " << seed << ": the rule takes the smear";
    EXPECT_LT((tip.position - Vec3(front, bottom, 0.0)).norm(), 0.007)
        << "seed " << seed << ", tip at " << tip.position.transpose();
  }
}

// A scoop's tip is its far end: the point farthest from the hand, which is a rim's corner (off the
// handle's line), projected onto the symmetry plane, so at the rim's height. A fringe 8 mm deep beyond the
// middle of the far edge reaches farther from the hand than the corners do, but along the handle, within
// the noise of the tie; across the handle the corners stand 5 cm out.
TEST(TooltipEdge, ScoopTipIsTheFarEdgesRimCornerNotTheFringeInItsMiddle) {
  const double depth = 0.02, half_width = 0.045, far_end = -0.25;
  Rng rng(9);
  Points scoop;
  for (double y = -0.15; y >= far_end; y -= 0.001)
    for (double z = -half_width; z <= half_width + 1e-9; z += 0.001)
      scoop.push_back(Vec3(depth * (z / half_width) * (z / half_width), y + rng.uniform(-0.0015, 0.0015), z));
  for (double y = far_end; y >= far_end - 0.008; y -= 0.001)
    for (double z = -0.02; z <= 0.02; z += 0.001)
      if (rng.uniform() > (far_end - y) / 0.008) scoop.push_back(Vec3(0.0, y, z));
  ToolFrame frame;
  frame.origin = Vec3(0.0, -0.15, 0.0);
  frame.head_kind = HeadKind::scoop;
  const Tooltip tip = find_tooltip(scoop, frame);
  EXPECT_NEAR(tip.position.x(), depth, 0.005) << "tip at " << tip.position.transpose();
  EXPECT_NEAR(tip.position.y(), far_end, 0.005) << "tip at " << tip.position.transpose();
  EXPECT_EQ(tip.position.z(), 0.0);
}

// A hand holds the handle off its axis: here 6 cm to the side of a blade 12 cm wide whose far edge comes to
// a point over its last 2 cm. From the hand, the corner on the other side where the point begins lies as
// far (259 mm) as the point (257 mm), and the tie would go to the corner, 2 cm short of the far end and 6 cm
// to the side; from the handle's axis, the point is the far end by 12 mm (250 against 238). The frame's
// JSON keeps the handle's point, so find-tooltip given the file finds the same tip.
TEST(TooltipEdge, ABladesFarEndIsMeasuredFromTheHandlesAxisNotTheHand) {
  const double side = 0.06, half_width = 0.06, far_end = -0.25, taper = 0.02;
  for (std::uint32_t seed = 1; seed <= 5; ++seed) {
    Rng rng(seed);
    Points blade;
    for (double y = -0.10; y >= far_end; y -= 0.001) {
      const double half = y >= far_end + taper ? half_width : half_width * (y - far_end) / taper;
      for (double z = -half; z <= half + 1e-9; z += 0.001)
        blade.push_back(Vec3(rng.uniform(-0.001, 0.001), y + rng.uniform(-0.001, 0.001), side + z));
    }
    ToolFrame frame;
    frame.origin = Vec3(0.0, -0.17, side);
    frame.handle_point = Vec3(0.0, -0.05, side);
    frame.head_kind = HeadKind::blade;
    // The rule's point, before the projection onto the symmetry plane and the edge's retreat (a point's
    // apex is as sparse as a fringe, FringeRetreatsTowardsTheEdge...): on the point, within the tie
    // (tie-tolerance, 5 mm) of its apex, where the tie-break takes the widest, not at the corner.
    const Tooltip tip = find_tooltip(blade, frame);
    EXPECT_NEAR(tip.surface_point.y(), far_end, 0.006) << "seed " << seed << ", at " << tip.surface_point.transpose();
    EXPECT_NEAR(tip.surface_point.z(), side, 0.03) << "seed " << seed << ", at " << tip.surface_point.transpose();
    const ToolFrame read = tool_frame_from_json(tool_frame_json(frame, ToolFrameConfig{}), "blade.json");
    EXPECT_TRUE(read.handle_point.isApprox(frame.handle_point, 1e-12));
    EXPECT_TRUE(find_tooltip(blade, read).position.isApprox(tip.position, 1e-9)) << "seed " << seed;
  }
}

// Stereo smears a plate seen face-on into a tail behind it, as deep as the gap to the background: at the
// blade's far end that tail reaches as far from the hand as the plate, and where across the blade the tip
// lies is uncertain. A clean plate's far end spreads across it by its thickness and noise only.
TEST(TooltipEdge, SmearAcrossABladesFarEndMakesTheTipDoubtful) {
  const double half_width = 0.045, far_end = -0.25;
  const auto spread_doubt = [](const Tooltip& tip) {
    return std::any_of(tip.confidence.doubts.begin(), tip.confidence.doubts.end(),
                       [](const std::string& d) { return d.find("far end spreads") != std::string::npos; });
  };
  ToolFrame frame;
  frame.origin = Vec3(0.0, -0.15, 0.0);
  frame.head_kind = HeadKind::blade;
  for (std::uint32_t seed = 1; seed <= 5; ++seed) {
    Rng rng(seed);
    Points blade;
    for (double y = -0.15; y >= far_end; y -= 0.001)
      for (double z = -half_width; z <= half_width + 1e-9; z += 0.001)
        blade.push_back(Vec3(rng.uniform(-0.002, 0.002), y + rng.uniform(-0.0015, 0.0015), z));
    const Tooltip clean = find_tooltip(blade, frame);
    EXPECT_FALSE(spread_doubt(clean)) << "seed " << seed;
    // The tail: 1 to 4 cm behind the plate over the last centimetre of it, half as dense as the plate.
    for (double y = far_end; y <= far_end + 0.01; y += 0.001)
      for (double z = -half_width; z <= half_width + 1e-9; z += 0.002)
        for (double x = -0.04; x <= -0.01; x += 0.002) blade.push_back(Vec3(x, y + rng.uniform(-0.0015, 0.0015), z));
    const Tooltip smeared = find_tooltip(blade, frame);
    EXPECT_TRUE(spread_doubt(smeared)) << "seed " << seed << ", tip at " << smeared.position.transpose();
    EXPECT_FALSE(smeared.confidence.confident) << "seed " << seed;
  }
}

// A blade is told from the head seen along the handle, before any plane is chosen: the shovel's scoop is
// one (a plate centred on the handle's axis, reaching along it), and its plane is the one across it; a
// hook or an L (reaching out on one side), a T's bar and a rake's comb (short along the handle) and a
// hoe's blade (a head's length in front) are not.
TEST(ToolFrameAccuracy, BladesAreCentredPlatesAlongTheHandle) {
  constexpr int kGrasps = 12;
  int blades = 0;
  for (int g = 0; g < kGrasps; ++g) {
    const auto shovel = make_held_tool(ToolFamily::shovel, 110u + g);
    const ToolFrame frame = estimate_tool_frame(shovel.observed);
    blades +=
        frame.tip_at_far_end() &&
        std::abs(frame.symmetry_axis().dot(shovel.grasp.topLeftCorner<3, 3>().col(2))) >= std::cos(10 * M_PI / 180);
    for (ToolFamily family :
         {ToolFamily::hook, ToolFamily::l_stick, ToolFamily::t_bar, ToolFamily::rake, ToolFamily::hoe}) {
      const auto other = make_held_tool(family, 110u + g);
      EXPECT_FALSE(estimate_tool_frame(other.observed).diagnostics.head_is_blade)
          << to_string(family) << " grasp " << g;
    }
  }
  // A grasp may hide a wing behind the hand's cut.
  EXPECT_GE(blades, kGrasps - 2) << blades << " of " << kGrasps << " shovels a blade with the plane across it";
}

// Smear behind a head (a sparse sheet along the cameras' rays, 6 % of its points) can reach as far back as
// the head reaches forward: the reaches no longer tell the side. The head's points on average still lie
// in front, so X points there, and the side is reported doubtful.
TEST(ToolFrameAccuracy, SmearBehindTheHeadDoesNotReverseTheEffector) {
  int right = 0;
  constexpr int kGrasps = 8;
  for (int g = 0; g < kGrasps; ++g) {
    auto hoe = make_held_tool(ToolFamily::hoe, 90u + g);
    const Eigen::Matrix3d rotation = hoe.grasp.topLeftCorner<3, 3>();
    const Vec3 translation = hoe.grasp.topRightCorner<3, 1>();
    Rng rng(static_cast<std::uint32_t>(g));
    const double far_y = -hoe.shape.handle_length - hoe.shape.head_height;
    const std::size_t smear = hoe.observed.size() / 16;
    for (std::size_t k = 0; k < smear; ++k) {
      const Vec3 canonical(-rng.uniform(0.02, hoe.shape.head_length + 0.01),
                           rng.uniform(far_y, -hoe.shape.handle_length), rng.uniform(-0.005, 0.005));
      hoe.observed.push_back(rotation * canonical + translation);
    }
    const ToolFrame frame = estimate_tool_frame(hoe.observed);
    EXPECT_FALSE(frame.diagnostics.salient_effector) << "grasp " << g << ": the smear should make the reaches alike";
    right += frame.effector_axis().dot(rotation.col(0)) > 0;
  }
  EXPECT_GE(right, kGrasps - 1) << right << " of " << kGrasps;
}

// The rules: a hoe's blade reaches forward only: its effector side is clear. A T-bar's crossbar reaches
// alike both ways: nothing decides its side, and find-tooltip reports the tip at the bar's other end.
TEST(ToolFrameAccuracy, UndecidedEffectorSideGivesTheOtherSidesTip) {
  for (int g = 0; g < 4; ++g) {
    const auto hoe = make_held_tool(ToolFamily::hoe, 70u + g);
    EXPECT_TRUE(estimate_tool_frame(hoe.observed, kRules).effector_side_clear) << "hoe grasp " << g;
    const auto bar = make_held_tool(ToolFamily::t_bar, 70u + g);
    const ToolFrame frame = estimate_tool_frame(bar.observed, kRules);
    ASSERT_FALSE(frame.effector_side_clear) << "t-bar grasp " << g;
    const Tooltip tip = find_tooltip(bar.observed, frame);
    const auto other = std::find_if(tip.alternatives.begin(), tip.alternatives.end(),
                                    [](const TooltipAlternative& a) { return a.source == "other effector side"; });
    ASSERT_NE(other, tip.alternatives.end()) << "t-bar grasp " << g;
    // The bar's two ends lie its length apart, on either side of the handle.
    EXPECT_GT((other->position - tip.position).norm(), 0.5 * bar.shape.head_length) << "t-bar grasp " << g;
    EXPECT_FALSE(tip.confidence.confident);
  }
}
