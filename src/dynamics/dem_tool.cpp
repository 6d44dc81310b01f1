// DemSystem's rod (README, "Rodding"): a kinematic capsule on a prescribed path, one more
// wall entry of the neighbour list after the container's planes.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "aggpack/dynamics/dem_system.hpp"
#include "dem_system_internal.hpp"

namespace aggpack {

namespace {
// The segment of the path that holds time t (its index k: from path[k] to path[k + 1]), or
// none before the first point and after the last.
std::size_t segment_of(const std::vector<RodWaypoint>& path, double t) {
  const auto after = std::upper_bound(path.begin(), path.end(), t,
                                      [](double time, const RodWaypoint& p) { return time < p.time; });
  return static_cast<std::size_t>(after - path.begin());  // 0: before; size(): after the last
}
}  // namespace

Vec3 RodTool::tip_at(double t) const {
  const std::size_t k = segment_of(path, t);
  if (k == 0) return path.front().tip;
  if (k == path.size()) return path.back().tip;
  const RodWaypoint &a = path[k - 1], &b = path[k];
  const double f = (t - a.time) / (b.time - a.time);
  return a.tip + (b.tip - a.tip) * f;
}

Vec3 RodTool::velocity_at(double t) const {
  const std::size_t k = segment_of(path, t);
  if (k == 0 || k == path.size()) return {};
  const RodWaypoint &a = path[k - 1], &b = path[k];
  return (b.tip - a.tip) * (1.0 / (b.time - a.time));
}

double RodTool::distance(const Vec3& tip, const Vec3& x, Vec3& towards) const {
  // The nearest point of the axis segment [tip, tip + length e_z].
  const double along = std::clamp(x.z - tip.z, 0.0, length);
  const Vec3 d = Vec3{tip.x, tip.y, tip.z + along} - x;
  const double r = norm(d);
  // On the axis itself (a centre the rod has run through: the bed has blown up) any
  // horizontal normal will do.
  towards = r > 0.0 ? d * (1.0 / r) : Vec3{1.0, 0.0, 0.0};
  return r - radius;
}

void DemSystem::set_tool(std::optional<RodTool> tool) {
  if (tool) {
    const auto& path = tool->path;
    if (!(tool->radius > 0.0) || !(tool->length >= 0.0) || !std::isfinite(tool->radius + tool->length) || path.empty())
      throw std::invalid_argument("DemSystem::set_tool: a rod needs a radius > 0, a length >= 0 and a path");
    for (std::size_t k = 0; k < path.size(); ++k) {
      const RodWaypoint& p = path[k];
      if (!std::isfinite(p.time + p.tip.x + p.tip.y + p.tip.z) || (k > 0 && !(p.time > path[k - 1].time)))
        throw std::invalid_argument(fmt::format("DemSystem::set_tool: waypoint {} is not finite or not after the one before", k));
    }
  }
  // A new rod starts without the old one's contact history.
  const std::uint32_t rod_entry = n_ + container_.plane_count();
  for (std::size_t k = 0; k < other_.size(); ++k)
    if (other_[k] == rod_entry) {
      spring_[k] = {};
      if (rolling_history_) roll_[k] = {};
    }
  tool_ = std::move(tool);
  tool_force_ = {};
  tool_peak_ = 0.0;
  place_tool(time_);
  build_neighbour_list();
}

void DemSystem::redirect_tool(std::vector<RodWaypoint> path) {
  if (!tool_ || path.empty() || !(path.front().time == time_) || !(path.front().tip == tool_tip_))
    throw std::invalid_argument("DemSystem::redirect_tool: a new path must start at the rod's place now");
  for (std::size_t k = 1; k < path.size(); ++k)
    if (!(path[k].time > path[k - 1].time) || !std::isfinite(path[k].time + path[k].tip.x + path[k].tip.y + path[k].tip.z))
      throw std::invalid_argument(fmt::format("DemSystem::redirect_tool: waypoint {} is not finite or not after the one before", k));
  tool_->path = std::move(path);
  place_tool(time_);
}

double DemSystem::place_tool(double t) {
  if (!tool_) {
    tool_tip_ = tool_velocity_ = {};
    return 0.0;
  }
  tool_tip_ = tool_->tip_at(t);
  tool_velocity_ = tool_->velocity_at(t);
  return norm(tool_tip_ - listed_tool_tip_);
}

void DemSystem::sum_tool_force() {
  Vec3 sum{};
  for (const Vec3& f : tool_block_force_) sum += f;
  tool_force_ = sum;
  tool_peak_ = std::max(tool_peak_, norm(sum));
}

}  // namespace aggpack
