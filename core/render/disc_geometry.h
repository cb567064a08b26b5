#pragma once
// The plane geometry of numbered discs and their leader lines, shared by the layouts of item
// marks (mark_layout.h) and of placement targets (target_layout.h), so both follow one set of
// readability rules.

#include <Eigen/Core>
#include <vector>

namespace mtg::render {

/// Whether segments p1-p2 and q1-q2 cross (touching at an end counts, unless they share it); a
/// segment shorter than half a pixel (a disc on its anchor: no line) crosses nothing.
bool segments_cross(const Eigen::Vector2d& p1, const Eigen::Vector2d& p2, const Eigen::Vector2d& q1,
                    const Eigen::Vector2d& q2);

/// Distance from p to the segment a-b.
double distance_to_segment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b);

/// The candidate disc centres around an anchor, in the order they are tried: rings farther and
/// farther out (2 to 8.5 radii), and on each ring up first (a label above its object reads
/// best), then left and right alternately, down last.
std::vector<Eigen::Vector2d> disc_candidates(const Eigen::Vector2d& anchor, double r);

}  // namespace mtg::render
