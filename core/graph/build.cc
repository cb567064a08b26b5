#include "core/graph/build.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numeric>
#include <optional>

#include "core/graph/object_geometry.h"
#include "core/graph/overlap_check.h"
#include "core/graph/platforms.h"
#include "core/graph/sight_lines.h"
#include "core/graph/standing.h"
#include "core/util/stopwatch.h"

namespace mtg::graph {
namespace {

// A platform before names and frames exist.
struct Draft {
  ObjectId owner;
  Surface surface;
  std::string source;
  bool active = true;
};

std::string fmt_cm(double metres) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.1f cm", metres * 100.0);
  return buf;
}

std::string fmt_mm(double metres) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%g mm", metres * 1000.0);
  return buf;
}

double yaw_of(const Eigen::Isometry3d& X) {
  const Eigen::Vector3d x = X.linear().col(0);
  return std::atan2(x.y(), x.x());
}

// Classification that needs no support search: profile, geometry, floor contact. Objects off
// the floor stay kUnsupported until the support search places them.
void classify(const scene::Scene& scene, const IdVector<ObjectId, ObjectGeometry>& geo,
              const GraphOptions& options, SceneGraph& g) {
  for (const ObjectId i : g.objects.ids()) {
    const scene::ObjectInstance& src = scene.objects[i.index()];
    GraphObject& o = g.objects[i];
    o.name = src.name;
    o.template_name = src.template_name;
    o.short_name = src.short_name;
    o.category = src.category;
    if (const auto it = options.nouns.find(src.template_name); it != options.nouns.end()) {
      o.noun = it->second.singular;
      o.noun_plural = it->second.plural;
    }
    o.X_WO = src.X_WO;
    o.heading = yaw_of(src.X_WO);
    o.bottom = geo[i].bottom;
    o.top = geo[i].top;
    o.footprint = geo[i].footprint;
    o.excluded = options.exclude_templates.count(src.template_name) != 0;
    o.movable = !o.excluded && !src.articulated && src.motion != scene::MotionType::kStatic;
    o.kind = ObjectKind::kUnsupported;
    if (!geo[i].has_geometry()) {
      o.note = "no fixed geometry";
      g.warnings.push_back("object " + o.name +
                           " has no geometry outside its doors/drawers; left out of the graph");
    } else if (geo[i].bottom <= options.contact_tolerance) {
      if (o.height() < options.floor_covering_height &&
          std::abs(geom::signed_area(o.footprint)) >= options.floor_covering_min_area) {
        o.kind = ObjectKind::kFloorCovering;
      } else if (o.excluded) {
        o.kind = ObjectKind::kFixed;
        o.note = "scenery on the floor (excluded by scene profile " + options.profile_name + ")";
      } else if (o.height() < options.min_furniture_height && src.motion == scene::MotionType::kDynamic &&
                 !src.articulated) {
        // Too low to hold anything: a movable thing lying on the floor, which is no platform.
        o.kind = ObjectKind::kItem;
        o.note = "lies on the floor (not a platform: no task uses it)";
      } else {
        o.kind = ObjectKind::kFurniture;
      }
    }
  }
}

// The platform an object rests on (the paper's parent rule): the highest surface within
// [bottom - max_settle_drop, bottom + contact_tolerance] covering more than
// min_support_overlap of min(footprint, surface). An object lying across several supports at
// one level (a book across two books) is accepted when they cover that share of its footprint
// together; its parent is then the one under most of it. Returns the draft index or -1.
int find_support(ObjectId object, const ObjectGeometry& geometry, const std::vector<Draft>& drafts,
                 const GraphOptions& options) {
  const geom::Region footprint = geom::from_ring(geometry.footprint);
  const double foot_area = geom::area(footprint);
  struct Candidate {
    int draft;
    double height, overlap;
    bool alone;  // satisfies the rule by itself
  };
  std::vector<Candidate> candidates;
  for (std::size_t d = 0; d < drafts.size(); ++d) {
    const Draft& draft = drafts[d];
    if (draft.owner == object) continue;
    const double h = draft.surface.height;
    if (h > geometry.bottom + options.contact_tolerance) continue;
    if (h < geometry.bottom - options.max_settle_drop) continue;
    const double overlap = geom::area(geom::intersect(footprint, draft.surface.region));
    if (overlap <= 1e-6) continue;
    const bool alone = overlap > options.min_support_overlap * std::min(foot_area, draft.surface.area);
    candidates.push_back({static_cast<int>(d), h, overlap, alone});
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& a, const Candidate& b) { return a.height > b.height; });
  // Highest first: the first support that carries the object alone wins; failing that, supports
  // within 2 cm of each other that carry it together (the parent is the one under most of it).
  constexpr double kLevel = 0.02;
  for (std::size_t top = 0; top < candidates.size(); ++top) {
    if (candidates[top].alone) return candidates[top].draft;
    double combined = 0.0;
    std::size_t best = top;
    for (std::size_t k = top; k < candidates.size(); ++k) {
      if (candidates[k].height < candidates[top].height - kLevel) break;
      combined += candidates[k].overlap;
      if (candidates[k].overlap > candidates[best].overlap) best = k;
    }
    if (combined > options.min_support_overlap * foot_area) return candidates[best].draft;
  }
  return -1;
}

// Tolerances of the build that are not scene options (they are not tuned per dataset).
constexpr double kCeilingGap = 0.005;          // a surface counts as above a platform from 5 mm up
constexpr double kInterpenetration = 0.005;    // settled items may touch, not overlap by more than 5 mm
constexpr double kUsefulClearance = 0.1;       // an empty platform is worth visiting with 10 cm above it
constexpr double kCleanArea = 1e-4;            // polygon clean-up: slivers under 1 cm², ...
constexpr double kCleanDistance = 1e-3;        // ... and vertices closer than 1 mm
constexpr double kAboveTolerance = 1e-3;       // an object must rise 1 mm above a platform to cover it

constexpr double kReachStep = 0.02;             // m between the sample points of a covered surface
constexpr double kReachLow = 0.04;              // the lowest reach line: over a lip, under a door
constexpr double kReachMinDepth = 0.08;         // a reached piece narrower than this holds nothing

// The part of a platform inside its own owner (a shelf, a TV stand's floor) that an arm reaches
// through the opening: the sample points, every 2 cm, from which a horizontal line out of a side
// the robot can use, 4 cm above the surface or at half its free height, passes none of the owner's
// triangles. A TV stand's floor runs on behind its closed doors, and its 3x3 cells were drawn on
// the doors (issue 53). Doors and drawers of articulated furniture are not among the owner's
// triangles (object_geometry.h): they count as open, as the paper treats fridge shelves. nullopt
// when every point is reached (the platform stays as it was); an empty region when none is.
std::optional<geom::Region> reachable_part(const Platform& p, const geom::TriangleSoup& owner) {
  if (!p.interior || !std::isfinite(p.clearance)) return std::nullopt;
  static const Eigen::Vector2d kOut[4] = {{0, -1}, {-1, 0}, {0, 1}, {1, 0}};  // rear, left, front, right in P
  std::vector<Eigen::Vector3d> out_W;
  for (const Side side : kSides) {
    if (!p.sides[static_cast<std::size_t>(side)].usable()) continue;
    // Far enough to leave any furniture: only the owner's own triangles can block it.
    const Eigen::Vector2d d = p.X_WP.linear() * kOut[static_cast<std::size_t>(side)] * 5.0;
    out_W.emplace_back(d.x(), d.y(), 0.0);
  }
  if (out_W.empty()) return std::nullopt;
  std::vector<double> heights{p.height + kReachLow};
  if (p.clearance / 2.0 > kReachLow) heights.push_back(p.height + p.clearance / 2.0);
  // A horizontal line can only meet a triangle that spans its height: each line tests those.
  std::vector<geom::TriangleSoup> across(heights.size());
  for (const geom::Triangle& t : owner.triangles) {
    for (std::size_t k = 0; k < heights.size(); ++k) {
      if (std::min({t.a.z(), t.b.z(), t.c.z()}) <= heights[k] && std::max({t.a.z(), t.b.z(), t.c.z()}) >= heights[k]) {
        across[k].add(t);
      }
    }
  }
  const Eigen::Vector2d size = p.box_P.sizes();
  const int nx = std::max(1, static_cast<int>(std::ceil(size.x() / kReachStep)));
  const int ny = std::max(1, static_cast<int>(std::ceil(size.y() / kReachStep)));
  const Eigen::Vector2d cell(size.x() / nx, size.y() / ny);
  bool every = true;
  std::vector<geom::Ring> reached;  // one rectangle per run of reached cells in a row
  for (int iy = 0; iy < ny; ++iy) {
    int run = -1;  // first cell of the current run
    for (int ix = 0; ix <= nx; ++ix) {
      bool reach = false;
      if (ix < nx) {
        const Eigen::Vector2d c_P = p.box_P.min() + Eigen::Vector2d((ix + 0.5) * cell.x(), (iy + 0.5) * cell.y());
        if (geom::contains(p.polygon_P, c_P)) {
          const Eigen::Vector2d q = p.X_WP * c_P;
          for (std::size_t k = 0; k < heights.size(); ++k) {
            for (const Eigen::Vector3d& dir : out_W) {
              reach = reach || !geom::ray_blocked(across[k], Eigen::Vector3d(q.x(), q.y(), heights[k]), dir, 1e-6, 1.0);
            }
          }
          every = every && reach;
        }
      }
      if (reach && run < 0) run = ix;
      if (!reach && run >= 0) {
        const Eigen::Vector2d lo = p.box_P.min() + Eigen::Vector2d(run * cell.x(), iy * cell.y());
        const Eigen::Vector2d hi = p.box_P.min() + Eigen::Vector2d(ix * cell.x(), (iy + 1) * cell.y());
        reached.push_back(geom::rectangle(lo, hi).rings.front());
        run = -1;
      }
    }
  }
  if (every) return std::nullopt;
  if (reached.empty()) return geom::Region{};
  const double h = kReachMinDepth / 2.0;
  const geom::Ring square{{-h, -h}, {h, -h}, {h, h}, {-h, h}};
  const geom::Region reach = geom::unite_rings(reached);
  // Only a place an item could stand on counts as closed off (behind a door, a panel): the strip
  // where a shelf's outline runs a centimetre into its walls stays as it was.
  if (geom::erode(geom::subtract(p.polygon_P, reach), square).empty()) return std::nullopt;
  // What an item cannot stand on goes: the ledge in front of a closed door, a sliver beside it
  // (opened with an 8 cm square, which keeps the rectangles of the reached cells as they are).
  return geom::intersect(p.polygon_P, geom::dilate(geom::erode(reach, square), square));
}

// The build's phases, in order, over shared state (the graph being built and what it needs).
class GraphBuilder {
 public:
  GraphBuilder(const scene::Scene& scene, const GraphOptions& options) : scene_(scene), options_(options) {}

  SceneGraph build(BuildTimings& t) {
    Stopwatch total, watch;
    measure_and_classify();
    t.geometry = watch.elapsed_ms();
    watch.reset();
    collect_platform_drafts();
    t.platforms = watch.elapsed_ms();
    watch.reset();
    settle_bottom_up();
    t.settle = watch.elapsed_ms();
    make_platforms();
    assign_headings();
    frame_platforms();
    watch.reset();
    measure_clearance();
    t.clearance = watch.elapsed_ms();
    watch.reset();
    check_interpenetration();
    t.overlap = watch.elapsed_ms();
    watch.reset();
    find_standing_areas();
    t.standing = watch.elapsed_ms();
    t.total = total.elapsed_ms();
    return std::move(g_);
  }

 private:
  std::size_t size() const { return scene_.objects.size(); }
  IdRange<ObjectId> object_ids() const { return IdRange<ObjectId>(size()); }
  // The scene's objects and the graph's are in the same order.
  const scene::ObjectInstance& source(ObjectId i) const { return scene_.objects[i.index()]; }

  // Geometry in the world, classification, and whatever stands on the floor moved to z = 0.
  void measure_and_classify() {
    g_.scene = scene_.name;
    g_.noun_covers = options_.noun_covers;
    g_.objects.resize(size());
    geo_.resize(size());
    for (const ObjectId i : object_ids()) geo_[i] = object_geometry(source(i));
    classify(scene_, geo_, options_, g_);
    for (const ObjectId i : object_ids()) {
      if (g_.objects[i].kind != ObjectKind::kUnsupported) settle(i, -geo_[i].bottom);
    }
  }

  // Moves object i (its geometry and its pose) up or down by dz.
  void settle(ObjectId i, double dz) {
    GraphObject& o = g_.objects[i];
    translate(geo_[i], Eigen::Vector3d(0, 0, dz));
    o.X_WO.translation().z() += dz;
    o.settle_dz = dz;
    o.bottom = geo_[i].bottom;
    o.top = geo_[i].top;
  }

  // Furniture platforms are active (declared-receptacle furniture keeps reserves); surfaces of
  // items and scenery are reserves that only become platforms when something rests on them.
  void add_drafts(ObjectId i, bool furniture) {
    for (auto& c : platform_candidates(source(i), g_.objects[i].X_WO, geo_[i], options_, g_.warnings)) {
      drafts_.push_back({i, std::move(c.surface),
                         furniture ? std::move(c.source) : std::string("mesh:supports-item"), furniture && c.active});
    }
  }

  void collect_platform_drafts() {
    for (const ObjectId i : object_ids()) {
      if (g_.objects[i].kind == ObjectKind::kFurniture) add_drafts(i, true);
      if (g_.objects[i].kind == ObjectKind::kFixed) add_drafts(i, false);
    }
  }

  // Settle everything else bottom-up: each object drops onto the highest platform below it
  // that supports its footprint; once settled, its own surfaces can support what lies above.
  // What rests on nothing is fixed to the structure (wall-mounted furniture or scenery) unless
  // it is a movable object: then it is reported.
  void settle_bottom_up() {
    for (const ObjectId i : object_ids()) {
      if (g_.objects[i].kind == ObjectKind::kUnsupported && geo_[i].has_geometry()) pending_.push_back(i);
    }
    std::stable_sort(pending_.begin(), pending_.end(),
                     [&](ObjectId a, ObjectId b) { return geo_[a].bottom < geo_[b].bottom; });
    parent_draft_.assign(size(), -1);
    int far_drops = 0;
    double max_drop = 0.0;
    for (const ObjectId i : pending_) {
      GraphObject& o = g_.objects[i];
      const bool falls = !source(i).articulated && source(i).motion != scene::MotionType::kStatic;
      // Fixed objects (STATIC, articulated) do not fall: they attach only within the tolerance.
      GraphOptions search = options_;
      if (!falls) search.max_settle_drop = options_.contact_tolerance;
      const int d = find_support(i, geo_[i], drafts_, search);
      if (d < 0) {
        rests_on_nothing(i);
        continue;
      }
      Draft& support = drafts_[static_cast<std::size_t>(d)];
      support.active = true;
      o.kind = o.movable ? ObjectKind::kItem : ObjectKind::kFixed;
      if (o.excluded) o.note = "scenery (excluded by scene profile " + options_.profile_name + ")";
      parent_draft_[i] = d;
      const double dz = support.surface.height - geo_[i].bottom;
      settle(i, dz);
      if (std::abs(dz) > options_.contact_tolerance) {
        ++far_drops;
        max_drop = std::max(max_drop, std::abs(dz));
        o.note += std::string(o.note.empty() ? "" : "; ") + "settled " + fmt_cm(dz) + " (beyond the " +
                  fmt_cm(options_.contact_tolerance) + " contact tolerance)";
      }
      add_drafts(i, false);
    }
    if (far_drops > 0) {
      g_.warnings.push_back(std::to_string(far_drops) + " object(s) settled from more than " +
                            fmt_cm(options_.contact_tolerance) + " above their platform (largest " +
                            fmt_cm(max_drop) + "; see each object's note)");
    }
  }

  void rests_on_nothing(ObjectId i) {
    GraphObject& o = g_.objects[i];
    if (o.movable) {
      o.note = "rests on no platform";
      g_.warnings.push_back("object " + o.name + " cannot be placed: no platform within " +
                            fmt_cm(options_.max_settle_drop) + " below it supports it");
    } else if (o.excluded) {
      o.kind = ObjectKind::kFixed;
      o.note = "scenery fixed to the structure (excluded by scene profile " + options_.profile_name + ")";
      add_drafts(i, false);
    } else {
      o.kind = ObjectKind::kFurniture;
      o.note = "fixed to the structure (wall-mounted)";
      add_drafts(i, true);
    }
  }

  // Platforms: active drafts, per owner bottom-up; then each settled object's parent.
  void make_platforms() {
    draft_to_platform_.assign(drafts_.size(), PlatformId());
    std::vector<int> order(drafts_.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
      const Draft& x = drafts_[static_cast<size_t>(a)];
      const Draft& y = drafts_[static_cast<size_t>(b)];
      if (x.owner != y.owner) return x.owner < y.owner;
      if (x.surface.height != y.surface.height) return x.surface.height < y.surface.height;
      return x.surface.area > y.surface.area;
    });
    for (const int d : order) {
      const Draft& draft = drafts_[static_cast<size_t>(d)];
      if (!draft.active) continue;
      GraphObject& owner = g_.objects[draft.owner];
      Platform p;
      p.owner = draft.owner;
      p.index = static_cast<int>(owner.platforms.size());
      p.name = owner.name + "_platform_" + std::to_string(p.index);
      p.height = draft.surface.height;
      p.source = draft.source;
      p.destination = owner.kind == ObjectKind::kFurniture;
      const PlatformId id = g_.platforms.push_back(std::move(p));
      draft_to_platform_[static_cast<size_t>(d)] = id;
      owner.platforms.push_back(id);
    }
    for (const ObjectId i : object_ids()) {
      if (parent_draft_[i] < 0) continue;
      const PlatformId p = draft_to_platform_[static_cast<size_t>(parent_draft_[i])];
      g_.objects[i].parent = p;
      g_.platforms[p].items.push_back(i);
    }
  }

  // Headings: furniture from its canonical minimum-area rectangle; everything on it inherits.
  void assign_headings() {
    for (GraphObject& o : g_.objects) {
      if (o.kind == ObjectKind::kFurniture && o.footprint.size() >= 3) {
        o.heading = geom::min_area_rect(o.footprint, yaw_of(o.X_WO)).yaw;
      }
    }
    for (const ObjectId oi : pending_) {  // bottom-up, so parents come first
      GraphObject& o = g_.objects[oi];
      if (o.parent.valid()) o.heading = g_.objects[g_.platforms[o.parent].owner].heading;
    }
  }

  // Platform frames (aligned with the owner's heading, centred on the surface) and polygons.
  void frame_platforms() {
    for (std::size_t d = 0; d < drafts_.size(); ++d) {
      const PlatformId pi = draft_to_platform_[d];
      if (!pi.valid()) continue;
      Platform& p = g_.platforms[pi];
      const double yaw = g_.objects[p.owner].heading;
      const geom::Region region_W = geom::clean(drafts_[d].surface.region, kCleanArea, kCleanDistance);
      const Eigen::Rotation2Dd R_HW(-yaw);
      Eigen::AlignedBox2d box_H;
      for (const auto& ring : region_W.rings) {
        for (const auto& q : ring) box_H.extend(R_HW * q);
      }
      p.X_WP = Eigen::Translation2d(Eigen::Rotation2Dd(yaw) * box_H.center()) * Eigen::Rotation2Dd(yaw);
      p.polygon_P = geom::transform(region_W, p.X_WP.inverse());
      p.box_P = geom::bounds(p.polygon_P);
    }
  }

  // Detected once per object and direction, and only when asked: an object's upward surfaces
  // matter only above its own platforms (interior layers), its downward ones above anyone's.
  const std::vector<Surface>& surfaces(ObjectId oi, bool upward) {
    auto it = surfaces_of_.find({oi, upward});
    if (it == surfaces_of_.end()) {
      it = surfaces_of_
               .emplace(std::make_pair(oi, upward), detect_surfaces(geo_[oi].soup, upward, surface_options(options_)))
               .first;
    }
    return it->second;
  }

  // Clearance and interior layers: surfaces above covering most of the platform.
  void measure_clearance() {
    for (Platform& p : g_.platforms) {
      const geom::Region region_W = p.polygon_W();
      const double area = geom::area(region_W);
      const Eigen::AlignedBox2d box_W = geom::bounds(region_W);
      auto covered_by = [&](const std::vector<Surface>& above_list, bool own) {
        for (const Surface& above : above_list) {
          if (above.height <= p.height + kCeilingGap) continue;
          if (geom::area(geom::intersect(region_W, above.region)) <= options_.ceiling_coverage * area) continue;
          p.clearance = std::min(p.clearance, above.height - p.height);
          if (own) p.interior = true;
        }
      };
      for (const ObjectId i : object_ids()) {
        const GraphObject& o = g_.objects[i];
        const bool own = i == p.owner;
        // Static geometry only: items move, floor coverings lie below everything.
        if (!own && o.kind != ObjectKind::kFurniture && o.kind != ObjectKind::kFixed) continue;
        if (!geo_[i].has_geometry() || geo_[i].top <= p.height + kAboveTolerance) continue;
        const Eigen::AlignedBox2d ob(Eigen::Vector2d(geo_[i].soup.bounds.min().head<2>()),
                                     Eigen::Vector2d(geo_[i].soup.bounds.max().head<2>()));
        if (!ob.intersects(box_W)) continue;
        covered_by(surfaces(i, false), own);
        if (own) covered_by(surfaces(i, true), own);
      }
    }
  }

  // Settled items must not interpenetrate (FCL on their meshes).
  void check_interpenetration() {
    std::vector<const geom::TriangleSoup*> meshes;
    for (const auto& gg : geo_) meshes.push_back(&gg.soup);
    std::vector<std::pair<int, int>> candidates;  // positions in `meshes`, which are the objects' ids
    for (const Platform& p : g_.platforms) {
      for (std::size_t a = 0; a < p.items.size(); ++a) {
        for (std::size_t b = a + 1; b < p.items.size(); ++b) {
          const auto& fa = g_.objects[p.items[a]].footprint;
          const auto& fb = g_.objects[p.items[b]].footprint;
          if (geom::bounds(fa).intersects(geom::bounds(fb))) {
            candidates.emplace_back(p.items[a].value(), p.items[b].value());
          }
        }
      }
    }
    for (const auto& [a, b] : interpenetrating_pairs(meshes, candidates, kInterpenetration)) {
      g_.warnings.push_back("objects " + g_.objects[ObjectId(a)].name + " and " +
                            g_.objects[ObjectId(b)].name + " interpenetrate by more than " +
                            fmt_mm(kInterpenetration) + " in the settled state");
    }
  }

  // Everything on platform `p`, at any depth (an item's own platforms carry what stands on it).
  std::vector<ObjectId> objects_resting_on(const Platform& p) const {
    std::vector<ObjectId> out;
    std::vector<ObjectId> stack(p.items.rbegin(), p.items.rend());
    while (!stack.empty()) {
      const ObjectId o = stack.back();
      stack.pop_back();
      out.push_back(o);
      for (const PlatformId q : g_.objects[o].platforms) {
        const auto& on = g_.platforms[q].items;
        stack.insert(stack.end(), on.rbegin(), on.rend());
      }
    }
    return out;
  }

  // What the view from each usable side of `p` shows of the objects on it (at any depth), and
  // so the side the robot arrives at.
  void count_objects_seen(Platform& p, const std::vector<Occluder>& occluders) const {
    std::vector<SightTarget> targets;
    double top = p.height;
    for (const ObjectId o : objects_resting_on(p)) {
      targets.push_back({o, Eigen::AlignedBox3d(geo_[o].soup.bounds)});
      top = std::max(top, g_.objects[o].top);
    }
    // An empty platform was left to the largest standing area: a chair's seat seen from behind
    // its backrest, the grid painted over the backrest (issue 53). From mtg-tasks/5 its surface
    // points choose the side as they do for a platform with items.
    if (targets.empty() && options_.platform_rules != PlatformRules::kReachedAndSeen) return;
    // And nine points of the surface itself: a side that looks past the furniture in front (a
    // TV stand seen from behind its TV) sees less of it.
    std::vector<Eigen::Vector3d> surface;
    const geom::Region poly_W = p.polygon_W();
    for (const double fx : {-0.35, 0.0, 0.35}) {
      for (const double fy : {-0.35, 0.0, 0.35}) {
        const geom::Point2 q = geom::closest_point(
            poly_W, p.X_WP * Eigen::Vector2d(fx * p.box_P.sizes().x(), fy * p.box_P.sizes().y()));
        surface.emplace_back(q.x(), q.y(), p.height + 0.01);
      }
    }
    const double eye_z = eye_height(p, p.height, top);
    for (const Side side : kSides) {
      SideInfo& info = p.sides[static_cast<std::size_t>(side)];
      if (!info.usable()) continue;
      const Eigen::Vector3d eye(info.standing_point.x(), info.standing_point.y(), eye_z);
      const Seen seen = count_seen(eye, targets, occluders);  // nothing seen of no targets
      info.objects_seen = seen.objects;
      info.sight_lines = seen.lines + clear_lines(eye, surface, occluders);
    }
    p.default_side = arrival_side(p);
  }

  // A covered platform becomes the part reached through its opening (reachable_part), its frame
  // centred on that part as every platform's is on its own box. What stands behind a closed door
  // stays where it is, on the platform, and is said once.
  void keep_reachable(Platform& p, const geom::Region& part) {
    for (const ObjectId o : p.items) {
      const geom::Point2 c = geom::centroid(geom::Region{{g_.objects[o].footprint}});
      if (!geom::contains(part, p.X_WP.inverse() * c)) {
        g_.warnings.push_back(g_.objects[o].name + " stands on " + p.name + " where no arm reaches through its opening");
      }
    }
    p.polygon_P = part;
    if (part.empty()) {
      for (SideInfo& side : p.sides) side.visible = false;  // nothing of it can be reached: no usable side
      p.default_side = -1;
      return;
    }
    const Eigen::Vector2d centre = geom::bounds(part).center();
    p.X_WP = p.X_WP * Eigen::Translation2d(centre);
    p.polygon_P = geom::transform(part, Eigen::Isometry2d(Eigen::Translation2d(-centre)));
    p.box_P = geom::bounds(p.polygon_P);
  }

  // Standing areas, visibility, navigability and the agent's numbering.
  void find_standing_areas() {
    // The robot is blocked by whatever stands on the floor (furniture and floor scenery).
    std::vector<const geom::TriangleSoup*> on_floor;
    std::vector<bool> steppable;
    for (const ObjectId i : object_ids()) {
      const GraphObject& o = g_.objects[i];
      const bool floor = o.kind == ObjectKind::kFurniture || o.kind == ObjectKind::kFixed;
      if (floor && !o.parent.valid() && o.bottom <= options_.contact_tolerance) {
        on_floor.push_back(&geo_[i].soup);
        // Light furniture a person steps around (a stool in front of a counter).
        steppable.push_back(o.kind == ObjectKind::kFurniture && o.movable &&
                            geom::area(geom::Region{{o.footprint}}) <= options_.steppable_max_area &&
                            o.height() <= options_.steppable_max_height);
      }
    }
    const FloorRaster raster(on_floor, steppable, options_);
    std::vector<Occluder> occluders;
    for (const ObjectId i : object_ids()) {
      if (g_.objects[i].kind != ObjectKind::kUnsupported && geo_[i].has_geometry()) occluders.push_back({i, &geo_[i].soup});
    }
    for (Platform& p : g_.platforms) {
      if (!p.destination) continue;
      const ObjectId owner = p.owner;
      evaluate_sides(p, g_.objects[owner].footprint, g_.objects[owner].heading, geo_[owner].soup, raster, options_);
      count_objects_seen(p, occluders);
      if (options_.platform_rules == PlatformRules::kReachedAndSeen) {
        if (const std::optional<geom::Region> part = reachable_part(p, geo_[owner].soup)) keep_reachable(p, *part);
      }
      const bool useful = !p.items.empty() || p.clearance > kUsefulClearance;
      p.navigable = p.height <= options_.max_platform_height && useful && p.default_side >= 0;
    }
    for (const GraphObject& o : g_.objects) {
      for (const PlatformId pi : o.platforms) {
        Platform& p = g_.platforms[pi];
        if (!p.navigable) continue;
        g_.navigable.push_back(pi);
        p.label = static_cast<int>(g_.navigable.size());
      }
    }
  }

  const scene::Scene& scene_;
  const GraphOptions& options_;
  SceneGraph g_;
  IdVector<ObjectId, ObjectGeometry> geo_;
  std::vector<Draft> drafts_;
  std::vector<ObjectId> pending_;               // objects settled bottom-up, in that order
  IdVector<ObjectId, int> parent_draft_;        // per object: the draft it rests on (-1: none)
  std::vector<PlatformId> draft_to_platform_;   // per draft: its platform (none: not a platform)
  std::map<std::pair<ObjectId, bool>, std::vector<Surface>> surfaces_of_;
};

}  // namespace

SceneGraph build_scene_graph(const scene::Scene& scene, const GraphOptions& options, BuildTimings* timings) {
  BuildTimings t;
  SceneGraph g = GraphBuilder(scene, options).build(t);
  if (timings != nullptr) *timings = t;
  return g;
}

}  // namespace mtg::graph
