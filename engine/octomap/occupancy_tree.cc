// OccupancyTree over liboctomap's OcTree: the only translation unit that includes OctoMap's headers.
#include "engine/octomap/occupancy_tree.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <unordered_map>

#include <octomap/OcTree.h>

#include "engine/octomap/octree_stream_check.h"
#include "schema/error.h"

namespace anchordb::engine {

namespace {

using octomap::OcTree;
using octomap::OcTreeKey;
using octomap::OcTreeNode;
using octomap::point3d;
constexpr unsigned kMaxDepth = 16;
constexpr std::string_view kOtMagic = "# Octomap OcTree file";
constexpr std::string_view kBtMagic = "# Octomap OcTree binary file";

std::uint64_t Pack(const OcTreeKey& k) {
  return std::uint64_t{k[0]} | (std::uint64_t{k[1]} << 16) | (std::uint64_t{k[2]} << 32);
}
OcTreeKey Unpack(std::uint64_t p) {
  return OcTreeKey(static_cast<octomap::key_type>(p & 0xffff), static_cast<octomap::key_type>((p >> 16) & 0xffff),
                   static_cast<octomap::key_type>((p >> 32) & 0xffff));
}

void Require(bool ok, const std::string& field, const std::string& what) {
  if (!ok) throw Error(ErrorCode::kUnprocessable, field + " " + what, field);
}

bool Finite(const Eigen::Vector3d& v) { return v.allFinite(); }

void ApplyParams(OcTree& tree, const OccupancyTreeParams& p) {
  tree.setProbHit(p.prob_hit);
  tree.setProbMiss(p.prob_miss);
  tree.setClampingThresMin(p.clamp_min);
  tree.setClampingThresMax(p.clamp_max);
  tree.setOccupancyThres(p.occupancy_threshold);
}

Eigen::Vector3d ToEigen(const point3d& p) { return {p.x(), p.y(), p.z()}; }
point3d ToPoint(const Eigen::Vector3d& v) {
  return point3d(static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z()));
}

// `box` cut to the addressable volume (2^15 leaves each way), where liboctomap's key conversion holds.
Box3 Addressable(const Box3& box, double resolution_m) {
  const double half = resolution_m * 32767.0;
  return {box.min_map.cwiseMax(Eigen::Vector3d::Constant(-half)).cwiseMin(Eigen::Vector3d::Constant(half)),
          box.max_map.cwiseMax(Eigen::Vector3d::Constant(-half)).cwiseMin(Eigen::Vector3d::Constant(half))};
}

bool Inside(const Box3& b, const Eigen::Vector3d& p) {
  return (p.array() >= b.min_map.array()).all() && (p.array() <= b.max_map.array()).all();
}

}  // namespace

void ValidateOccupancyTreeParams(const OccupancyTreeParams& p) {
  Require(std::isfinite(p.resolution_m) && p.resolution_m >= 0.005 && p.resolution_m <= 5.0, "resolution_m",
          "must be in [0.005, 5] m");
  Require(std::isfinite(p.prob_hit) && p.prob_hit > 0.5 && p.prob_hit < 1, "prob_hit", "must be in (0.5, 1)");
  Require(std::isfinite(p.prob_miss) && p.prob_miss > 0 && p.prob_miss < 0.5, "prob_miss", "must be in (0, 0.5)");
  Require(std::isfinite(p.clamp_min) && p.clamp_min > 0 && p.clamp_min <= p.prob_miss, "clamp_min",
          "must be in (0, prob_miss]");
  Require(std::isfinite(p.clamp_max) && p.clamp_max >= p.prob_hit && p.clamp_max < 1, "clamp_max",
          "must be in [prob_hit, 1)");
  Require(std::isfinite(p.occupancy_threshold) && p.occupancy_threshold > p.clamp_min &&
              p.occupancy_threshold < p.clamp_max,
          "occupancy_threshold", "must lie between clamp_min and clamp_max");
}

const char* VoxelStateName(VoxelState s) {
  switch (s) {
    case VoxelState::kFree: return "free";
    case VoxelState::kOccupied: return "occupied";
    case VoxelState::kUnknown: break;
  }
  return "unknown";
}

struct OccupancyTree::Impl {
  explicit Impl(const OccupancyTreeParams& p) : params(p), tree(p.resolution_m) { ApplyParams(tree, p); }
  Impl(const Impl& o) : params(o.params), tree(o.tree), stamps(o.stamps), base_stamp_ns(o.base_stamp_ns) {
    ApplyParams(tree, params);
  }
  OccupancyTreeParams params;
  OcTree tree;
  std::unordered_map<std::uint64_t, std::int64_t> stamps;  // finest-level key -> last update
  std::int64_t base_stamp_ns = 0;

  std::optional<std::int64_t> StampOf(const OcTreeKey& key) const {
    const auto it = stamps.find(Pack(key));
    if (it != stamps.end()) return it->second;
    if (base_stamp_ns != 0) return base_stamp_ns;
    return std::nullopt;
  }
  bool Addressable(const Eigen::Vector3d& p) const {
    OcTreeKey key;
    return tree.coordToKeyChecked(ToPoint(p), key);
  }
};

OccupancyTree::OccupancyTree(const OccupancyTreeParams& params) {
  ValidateOccupancyTreeParams(params);
  impl_ = std::make_unique<Impl>(params);
}
OccupancyTree::OccupancyTree(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
OccupancyTree::~OccupancyTree() = default;
OccupancyTree::OccupancyTree(OccupancyTree&&) noexcept = default;
OccupancyTree& OccupancyTree::operator=(OccupancyTree&&) noexcept = default;

OccupancyTree OccupancyTree::Clone() const {
  return OccupancyTree(std::make_unique<Impl>(*impl_));  // OcTree's deep copy
}

const OccupancyTreeParams& OccupancyTree::params() const { return impl_->params; }

void OccupancyTree::SetParams(const OccupancyTreeParams& params) {
  ValidateOccupancyTreeParams(params);
  if (params.resolution_m != impl_->params.resolution_m) {
    throw Error(ErrorCode::kUnprocessable, "resolution_m cannot change on an existing tree", "resolution_m");
  }
  impl_->params = params;
  ApplyParams(impl_->tree, params);
}

InsertStats OccupancyTree::InsertCloud(const std::vector<Eigen::Vector3f>& points_map, const Eigen::Vector3d& origin_map,
                                       double max_range_m, std::int64_t stamp_ns) {
  Require(Finite(origin_map), "origin", "must be finite");
  Require(impl_->Addressable(origin_map), "origin", "lies outside the tree's addressable volume");
  OcTree& tree = impl_->tree;
  if (const OcTreeNode* at_origin = tree.search(ToPoint(origin_map)); at_origin && tree.isNodeOccupied(at_origin)) {
    throw Error(ErrorCode::kUnprocessable, "origin lies inside an occupied voxel", "origin");
  }
  octomap::Pointcloud scan;
  scan.reserve(points_map.size());
  // The addressable half-extent: 2^15 leaves each way.
  const double half_extent_m = impl_->params.resolution_m * 32768.0 - impl_->params.resolution_m;
  for (std::size_t i = 0; i < points_map.size(); ++i) {
    const Eigen::Vector3f& p = points_map[i];
    if (!p.allFinite()) {
      throw Error(ErrorCode::kUnprocessable, "point " + std::to_string(i) + " is not finite", "points");
    }
    if (std::abs(p.x()) >= half_extent_m || std::abs(p.y()) >= half_extent_m || std::abs(p.z()) >= half_extent_m) {
      throw Error(ErrorCode::kUnprocessable, "point " + std::to_string(i) + " lies outside the addressable volume",
                  "points");
    }
    scan.push_back(p.x(), p.y(), p.z());
  }
  // As OcTree::insertPointCloud (computeUpdate, then free before occupied), with the stamp of each updated key.
  octomap::KeySet free_cells, occupied_cells;
  tree.computeUpdate(scan, ToPoint(origin_map), free_cells, occupied_cells, max_range_m > 0 ? max_range_m : -1.0);
  impl_->stamps.reserve(impl_->stamps.size() + free_cells.size() + occupied_cells.size());
  for (const OcTreeKey& key : free_cells) {
    tree.updateNode(key, false);
    impl_->stamps[Pack(key)] = stamp_ns;
  }
  for (const OcTreeKey& key : occupied_cells) {
    tree.updateNode(key, true);
    impl_->stamps[Pack(key)] = stamp_ns;
  }
  return {points_map.size(), free_cells.size(), occupied_cells.size()};
}

std::vector<PointOccupancy> OccupancyTree::Query(const std::vector<Eigen::Vector3d>& points_map) const {
  std::vector<PointOccupancy> out;
  out.reserve(points_map.size());
  const OcTree& tree = impl_->tree;
  for (std::size_t i = 0; i < points_map.size(); ++i) {
    if (!Finite(points_map[i])) {
      throw Error(ErrorCode::kUnprocessable, "point " + std::to_string(i) + " is not finite", "points");
    }
    PointOccupancy q;
    OcTreeKey key;
    if (!tree.coordToKeyChecked(ToPoint(points_map[i]), key)) {
      out.push_back(q);
      continue;
    }
    unsigned depth = 0;
    const OcTreeNode* node = tree.search(key, 0);
    if (node) {
      // Depth of the leaf that holds the key: walk down until a leaf.
      const OcTreeNode* n = tree.getRoot();
      for (depth = 0; depth < kMaxDepth && tree.nodeHasChildren(n); ++depth) {
        const unsigned child = octomap::computeChildIdx(key, static_cast<int>(kMaxDepth - 1 - depth));
        if (!tree.nodeChildExists(n, child)) break;
        n = tree.getNodeChild(n, child);
      }
      q.state = tree.isNodeOccupied(node) ? VoxelState::kOccupied : VoxelState::kFree;
      q.probability = node->getOccupancy();
      q.voxel_size_m = tree.getNodeSize(depth);
      q.stamp_ns = impl_->StampOf(key);
    }
    out.push_back(q);
  }
  return out;
}

RayHit OccupancyTree::CastRay(const Eigen::Vector3d& origin_map, const Eigen::Vector3d& direction_map,
                              double max_range_m, bool ignore_unknown) const {
  Require(Finite(origin_map), "origin", "must be finite");
  Require(Finite(direction_map) && direction_map.norm() > 1e-12, "direction", "must be finite and non-zero");
  Require(std::isfinite(max_range_m) && max_range_m > 0, "max_range_m", "must be positive");
  Require(impl_->Addressable(origin_map), "origin", "lies outside the tree's addressable volume");
  const OcTree& tree = impl_->tree;
  point3d end;
  RayHit hit;
  if (tree.castRay(ToPoint(origin_map), ToPoint(direction_map), end, ignore_unknown, max_range_m)) {
    hit.stopped_by = VoxelState::kOccupied;
  } else if (!ignore_unknown && tree.search(end) == nullptr) {
    hit.stopped_by = VoxelState::kUnknown;
  }
  hit.end_map = ToEigen(end);
  hit.distance_m = (hit.end_map - origin_map).norm();
  return hit;
}

std::vector<Voxel> OccupancyTree::OccupiedVoxels(const Box3& box_in, std::size_t limit, bool* truncated) const {
  Require(Finite(box_in.min_map) && Finite(box_in.max_map), "min", "must be finite");
  const Box3 box = Addressable(box_in, impl_->params.resolution_m);
  std::vector<Voxel> out;
  if (truncated) *truncated = false;
  const OcTree& tree = impl_->tree;
  if (tree.size() == 0) return out;
  for (auto it = tree.begin_leafs_bbx(ToPoint(box.min_map), ToPoint(box.max_map)), end = tree.end_leafs_bbx(); it != end;
       ++it) {
    if (!tree.isNodeOccupied(*it)) continue;
    const Eigen::Vector3d c = ToEigen(it.getCoordinate());
    if (!Inside(box, c)) continue;
    if (out.size() >= limit) {
      if (truncated) *truncated = true;
      break;
    }
    out.push_back({c, it.getSize(), it->getLogOdds(), impl_->StampOf(it.getKey())});
  }
  return out;
}

std::vector<Voxel> OccupancyTree::KnownVoxels(const Box3& box_in) const {
  Require(Finite(box_in.min_map) && Finite(box_in.max_map), "min", "must be finite");
  const Box3 box = Addressable(box_in, impl_->params.resolution_m);
  std::vector<Voxel> out;
  const OcTree& tree = impl_->tree;
  if (tree.size() == 0) return out;
  for (auto it = tree.begin_leafs_bbx(ToPoint(box.min_map), ToPoint(box.max_map)), end = tree.end_leafs_bbx(); it != end;
       ++it) {
    out.push_back({ToEigen(it.getCoordinate()), it.getSize(), it->getLogOdds(), std::nullopt});
  }
  return out;
}

TreeMetadata OccupancyTree::Metadata() const {
  const OcTree& tree = impl_->tree;
  TreeMetadata m;
  m.nodes = tree.size();
  m.memory_bytes = tree.memoryUsage();
  m.stamped_voxels = impl_->stamps.size();
  if (m.nodes == 0) return m;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    ++m.leaves;
    if (tree.isNodeOccupied(*it)) ++m.occupied_leaves;
    const Eigen::Vector3d c = ToEigen(it.getCoordinate());
    const double half = it.getSize() / 2;
    lo = lo.cwiseMin((c.array() - half).matrix());
    hi = hi.cwiseMax((c.array() + half).matrix());
  }
  if (m.leaves > 0) {
    m.min_map = lo;
    m.max_map = hi;
  }
  return m;
}

bool OccupancyTree::empty() const { return impl_->tree.size() == 0; }
std::int64_t OccupancyTree::base_stamp_ns() const { return impl_->base_stamp_ns; }
void OccupancyTree::set_base_stamp_ns(std::int64_t stamp_ns) { impl_->base_stamp_ns = stamp_ns; }

std::string OccupancyTree::WriteOt() const {
  std::ostringstream out(std::ios::binary);
  if (!impl_->tree.write(out)) throw Error(ErrorCode::kInternal, "the tree could not be written as .ot");
  return std::move(out).str();
}

std::string OccupancyTree::WriteBt() const {
  std::ostringstream out(std::ios::binary);
  if (!impl_->tree.writeBinaryConst(out)) throw Error(ErrorCode::kInternal, "the tree could not be written as .bt");
  return std::move(out).str();
}

namespace {

// Rejects what liboctomap would accept with only a warning on stderr: a stream cut short.
void RequireWholeStream(const std::istringstream& in, const char* what) {
  if (in.fail()) throw Error(ErrorCode::kInvalidArgument, std::string(what) + " is truncated or corrupt", "body");
}

// liboctomap's own header reader (a protected static member), so that the node bytes checked below are exactly the
// ones liboctomap goes on to read.
struct HeaderReader : octomap::AbstractOcTree {
  using octomap::AbstractOcTree::readHeader;
};

struct FileHeader {
  std::string id;
  unsigned size = 0;
  std::string_view nodes;  // the bytes after the header's `data` line
};

// Reads the header from `in` (a stream over `bytes`, at its start) and puts `in` back at the start, so that the one
// copy of the body serves the header check and liboctomap's read.
FileHeader ReadFileHeader(std::istringstream& in, std::string_view bytes, const char* what) {
  std::string first_line;
  std::getline(in, first_line);
  FileHeader h;
  double resolution_m = 0;
  if (!HeaderReader::readHeader(in, h.id, h.size, resolution_m)) {
    throw Error(ErrorCode::kInvalidArgument, std::string(what) + " has no complete header", "body");
  }
  const std::streamoff at = in.good() ? static_cast<std::streamoff>(in.tellg()) : -1;
  h.nodes = at >= 0 && static_cast<std::size_t>(at) <= bytes.size() ? bytes.substr(static_cast<std::size_t>(at))
                                                                    : std::string_view{};
  in.clear();
  in.seekg(0);
  return h;
}


}  // namespace

void OccupancyTree::ReadOt(std::string_view bytes, std::int64_t stamp_ns) {
  if (bytes.substr(0, kOtMagic.size()) != kOtMagic) {
    throw Error(ErrorCode::kInvalidArgument, "not an OctoMap .ot file (header '# Octomap OcTree file' missing)", "body");
  }
  // liboctomap builds whatever tree type the header names and reads a cut-off node stream past its end: only an
  // OcTree ("1" is its old name) whose nodes lie whole inside the body goes on.
  std::istringstream in(std::string(bytes), std::ios::binary);
  const FileHeader header = ReadFileHeader(in, bytes, ".ot file");
  if (header.id != "OcTree" && header.id != "1") {
    throw Error(ErrorCode::kInvalidArgument, ".ot file holds a '" + header.id + "', not an OcTree", "body");
  }
  CheckOtNodeStream(header.nodes);
  std::unique_ptr<octomap::AbstractOcTree> read(octomap::AbstractOcTree::read(in));
  if (!read) throw Error(ErrorCode::kInvalidArgument, ".ot file does not decode", "body");
  RequireWholeStream(in, ".ot file");
  auto* octree = dynamic_cast<OcTree*>(read.get());
  if (!octree) {
    throw Error(ErrorCode::kInvalidArgument, ".ot file holds a '" + read->getTreeType() + "', not an OcTree", "body");
  }
  OccupancyTreeParams params = impl_->params;
  params.resolution_m = octree->getResolution();
  ValidateOccupancyTreeParams(params);
  auto fresh = std::make_unique<Impl>(params);
  fresh->tree.swapContent(*octree);
  ApplyParams(fresh->tree, params);
  fresh->base_stamp_ns = stamp_ns;
  impl_ = std::move(fresh);
}

void OccupancyTree::ReadBt(std::string_view bytes, std::int64_t stamp_ns) {
  if (bytes.substr(0, kBtMagic.size()) != kBtMagic) {
    throw Error(ErrorCode::kInvalidArgument,
                "not an OctoMap .bt file (header '# Octomap OcTree binary file' missing)", "body");
  }
  // Resolution from the header, so the tree is built at the file's resolution (readBinary also sets it).
  // liboctomap reads a cut-off node stream past its end; it reads no nodes when the header's size is 0.
  std::istringstream in(std::string(bytes), std::ios::binary);
  const FileHeader header = ReadFileHeader(in, bytes, ".bt file");
  if (header.size > 0) CheckBtNodeStream(header.nodes);
  auto fresh = std::make_unique<Impl>(impl_->params);
  if (!fresh->tree.readBinary(in)) throw Error(ErrorCode::kInvalidArgument, ".bt file does not decode", "body");
  RequireWholeStream(in, ".bt file");
  fresh->params.resolution_m = fresh->tree.getResolution();
  ValidateOccupancyTreeParams(fresh->params);
  ApplyParams(fresh->tree, fresh->params);
  fresh->base_stamp_ns = stamp_ns;
  impl_ = std::move(fresh);
}

std::vector<std::pair<std::uint64_t, std::int64_t>> OccupancyTree::Stamps() const {
  std::vector<std::pair<std::uint64_t, std::int64_t>> out(impl_->stamps.begin(), impl_->stamps.end());
  std::sort(out.begin(), out.end());
  return out;
}

void OccupancyTree::RestoreStamps(const std::vector<std::pair<std::uint64_t, std::int64_t>>& stamps) {
  impl_->stamps.clear();
  impl_->stamps.reserve(stamps.size());
  for (const auto& [key, stamp] : stamps) impl_->stamps[key] = stamp;
}

bool OccupancyTree::SameLeaves(const OccupancyTree& other, float tolerance) const {
  const OcTree& a = impl_->tree;
  const OcTree& b = other.impl_->tree;
  if (a.getResolution() != b.getResolution() || a.size() != b.size()) return false;
  auto ia = a.begin_leafs(), ea = a.end_leafs();
  auto ib = b.begin_leafs(), eb = b.end_leafs();
  for (; ia != ea && ib != eb; ++ia, ++ib) {
    if (ia.getKey() != ib.getKey() || ia.getDepth() != ib.getDepth() ||
        std::abs(ia->getLogOdds() - ib->getLogOdds()) > tolerance) {
      return false;
    }
  }
  return ia == ea && ib == eb;
}

std::size_t OccupancyTree::ClearBox(const Box3& box_in, std::int64_t stamp_ns) {
  Require(Finite(box_in.min_map) && Finite(box_in.max_map) && (box_in.min_map.array() <= box_in.max_map.array()).all(), "min",
          "must be finite and not above max");
  const Box3 box = Addressable(box_in, impl_->params.resolution_m);
  OcTree& tree = impl_->tree;
  if (tree.size() == 0) return 0;
  OcTreeKey lo, hi;
  if (!tree.coordToKeyChecked(ToPoint(box.min_map), lo) || !tree.coordToKeyChecked(ToPoint(box.max_map), hi)) {
    throw Error(ErrorCode::kUnprocessable, "box lies outside the tree's addressable volume", "min");
  }
  // The finest keys of every known leaf in the box (a pruned leaf is split so only its part in the box changes).
  std::vector<OcTreeKey> keys;
  for (auto it = tree.begin_leafs_bbx(lo, hi), end = tree.end_leafs_bbx(); it != end; ++it) {
    const OcTreeKey k = it.getKey();
    const int span = 1 << (kMaxDepth - it.getDepth());
    const int base[3] = {k[0] - span / 2 * (span > 1), k[1] - span / 2 * (span > 1), k[2] - span / 2 * (span > 1)};
    for (int dx = 0; dx < span; ++dx) {
      const int x = base[0] + dx;
      if (x < lo[0] || x > hi[0]) continue;
      for (int dy = 0; dy < span; ++dy) {
        const int y = base[1] + dy;
        if (y < lo[1] || y > hi[1]) continue;
        for (int dz = 0; dz < span; ++dz) {
          const int z = base[2] + dz;
          if (z < lo[2] || z > hi[2]) continue;
          keys.emplace_back(static_cast<octomap::key_type>(x), static_cast<octomap::key_type>(y),
                            static_cast<octomap::key_type>(z));
        }
      }
    }
  }
  const float free_log_odds = tree.getClampingThresMinLog();
  std::size_t changed = 0;
  for (const OcTreeKey& key : keys) {
    const OcTreeNode* node = tree.search(key);
    if (node && node->getLogOdds() == free_log_odds) continue;
    tree.setNodeValue(key, free_log_odds);
    impl_->stamps[Pack(key)] = stamp_ns;
    ++changed;
  }
  return changed;
}

namespace {

// Appends the subtree of `node` (at `depth`, centre key `key`) in the .ot node layout (log-odds, child bit set,
// children), leaving out the leaves `stale` names; inner nodes take the largest log-odds of what remains of their
// children, as liboctomap's. Returns that log-odds, or nullopt when nothing of the subtree remains. (liboctomap 1.9's
// deleteNode frees an inner node that lost its last child with its child array still allocated, so the tree is
// rewritten instead of edited.)
template <typename Stale>
std::optional<float> WriteFreshNodes(const OcTree& tree, const OcTreeNode* node, unsigned depth, const OcTreeKey& key,
                                     const Stale& stale, std::string& out, std::size_t& nodes, std::size_t& removed) {
  if (!tree.nodeHasChildren(node)) {
    if (stale(key, depth)) {
      ++removed;
      return std::nullopt;
    }
    const float value = node->getLogOdds();
    out.append(reinterpret_cast<const char*>(&value), sizeof(value));
    out.push_back('\0');
    ++nodes;
    return value;
  }
  std::string children;
  unsigned char bits = 0;
  float largest = -std::numeric_limits<float>::infinity();
  const auto offset = static_cast<octomap::key_type>(32768 >> (depth + 1));
  for (unsigned i = 0; i < 8; ++i) {
    if (!tree.nodeChildExists(node, i)) continue;
    OcTreeKey child_key;
    octomap::computeChildKey(i, offset, key, child_key);
    if (const auto v = WriteFreshNodes(tree, tree.getNodeChild(node, i), depth + 1, child_key, stale, children, nodes,
                                       removed)) {
      bits = static_cast<unsigned char>(bits | (1u << i));
      largest = std::max(largest, *v);
    }
  }
  if (bits == 0) return std::nullopt;
  out.append(reinterpret_cast<const char*>(&largest), sizeof(largest));
  out.push_back(static_cast<char>(bits));
  out += children;
  ++nodes;
  return largest;
}

}  // namespace

std::size_t OccupancyTree::ForgetOlderThan(std::int64_t cutoff_ns) {
  OcTree& tree = impl_->tree;
  if (tree.size() == 0) return 0;
  // The newest stamp under every ancestor of a stamped key, so a pruned leaf is as fresh as its freshest part.
  std::unordered_map<std::uint64_t, std::int64_t> newest;  // (depth << 48 | ancestor key) -> stamp
  for (const auto& [packed, stamp] : impl_->stamps) {
    const OcTreeKey key = Unpack(packed);
    for (unsigned depth = 1; depth < kMaxDepth; ++depth) {
      const OcTreeKey ancestor = octomap::computeIndexKey(kMaxDepth - depth, key);
      std::int64_t& s = newest[(std::uint64_t{depth} << 48) | Pack(ancestor)];
      s = std::max(s, stamp);
    }
  }
  const auto stale = [&](const OcTreeKey& key, unsigned depth) {
    std::int64_t stamp = impl_->base_stamp_ns;
    if (depth == kMaxDepth) {
      if (const auto s = impl_->stamps.find(Pack(key)); s != impl_->stamps.end()) stamp = s->second;
    } else {
      const OcTreeKey ancestor = octomap::computeIndexKey(kMaxDepth - depth, key);
      if (const auto s = newest.find((std::uint64_t{depth} << 48) | Pack(ancestor)); s != newest.end()) {
        stamp = std::max(stamp, s->second);
      }
    }
    return stamp < cutoff_ns;
  };
  std::string body;
  std::size_t nodes = 0, removed = 0;
  const OcTreeKey root_key(32768, 32768, 32768);
  WriteFreshNodes(tree, tree.getRoot(), 0, root_key, stale, body, nodes, removed);
  if (removed == 0) return 0;
  OcTree fresh(impl_->params.resolution_m);
  if (nodes > 0) {
    std::ostringstream header;
    header.precision(17);
    header << kOtMagic << "\nid OcTree\nsize " << nodes << "\nres " << impl_->params.resolution_m << "\ndata\n";
    std::istringstream in(header.str() + body, std::ios::binary);
    std::unique_ptr<octomap::AbstractOcTree> read(octomap::AbstractOcTree::read(in));
    auto* rewritten = dynamic_cast<OcTree*>(read.get());
    if (!rewritten) throw Error(ErrorCode::kInternal, "the forgetting rewrite of the tree did not decode");
    fresh.swapContent(*rewritten);
  }
  tree.swapContent(fresh);
  ApplyParams(tree, impl_->params);
  for (auto it = impl_->stamps.begin(); it != impl_->stamps.end();) {
    it = it->second < cutoff_ns ? impl_->stamps.erase(it) : std::next(it);
  }
  return removed;
}

}  // namespace anchordb::engine
