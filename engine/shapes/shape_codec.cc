// The shape model blob: "ANCHSHM2", then the parameters, the codebook and the categories' vote bins and training
// sizes, little-endian (the host order of every supported target), strings length-prefixed. Version 1 ("ANCHSHM1")
// is read too: it lacks the three size parameters (after the seed) and the sizes (after each category's words);
// such a model verifies by votes only (size_weight 0).
#include <cmath>
#include <cstring>

#include "engine/shapes/shape_model.h"
#include "schema/error.h"

namespace anchordb::engine {
namespace {

constexpr char kMagic[8] = {'A', 'N', 'C', 'H', 'S', 'H', 'M', '2'};  // the last byte: the version
constexpr std::uint32_t kMaxCount = 1u << 26;

class Writer {
 public:
  template <typename T>
  void Pod(T v) {
    out_.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  void Str(const std::string& s) {
    Pod<std::uint32_t>(static_cast<std::uint32_t>(s.size()));
    out_ += s;
  }
  std::string Take() { return std::move(out_); }

 private:
  std::string out_;
};

class Reader {
 public:
  explicit Reader(std::string_view in) : in_(in) {}
  template <typename T>
  T Pod() {
    if (in_.size() - at_ < sizeof(T)) Fail("truncated");
    T v;
    std::memcpy(&v, in_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return v;
  }
  std::uint32_t Count() {
    const auto n = Pod<std::uint32_t>();
    if (n > kMaxCount || n > in_.size() - at_) Fail("a count exceeds the blob");
    return n;
  }
  std::string Str() {
    const auto n = Count();
    std::string s(in_.substr(at_, n));
    at_ += n;
    return s;
  }
  bool AtEnd() const { return at_ == in_.size(); }
  [[noreturn]] static void Fail(const std::string& why) {
    throw Error(ErrorCode::kInvalidArgument, "not a shape model blob: " + why, "model");
  }

 private:
  std::string_view in_;
  std::size_t at_ = 0;
};

}  // namespace

std::string EncodeShapeModel(const ShapeModel& m) {
  Writer w;
  for (char c : kMagic) w.Pod<char>(c);
  const auto& p = m.params;
  for (double v : {p.voxel_m, p.normal_radius_m, p.boundary_angle_rad, p.keypoint_spacing_m, p.shot_radius_m,
                   p.sphere_radius_m, p.detection_spacing_m, p.accept_fraction, p.merge_distance_m}) {
    w.Pod<double>(v);
  }
  for (int v : {p.codebook_size, p.activated_words, p.azimuth_bins, p.polar_bins, p.max_keypoints}) w.Pod<std::int32_t>(v);
  w.Pod<std::uint64_t>(p.seed);
  for (double v : {p.size_weight, p.size_bandwidth, p.size_floor}) w.Pod<double>(v);
  w.Pod<std::int32_t>(m.descriptor_dims);
  w.Pod<std::uint32_t>(static_cast<std::uint32_t>(m.codebook.size()));
  for (float v : m.codebook) w.Pod<float>(v);
  w.Pod<std::uint32_t>(static_cast<std::uint32_t>(m.categories.size()));
  for (const auto& c : m.categories) {
    w.Str(c.name);
    w.Pod<std::int32_t>(c.samples);
    w.Pod<std::int32_t>(c.keypoints);
    w.Pod<std::uint32_t>(static_cast<std::uint32_t>(c.words.size()));
    for (const auto& word : c.words) {
      w.Pod<std::uint32_t>(static_cast<std::uint32_t>(word.size()));
      for (const auto& b : word) {
        w.Pod<std::int32_t>(b.bin);
        w.Pod<float>(b.weight);
      }
    }
    w.Pod<std::uint32_t>(static_cast<std::uint32_t>(c.sizes.size()));
    for (const auto& size : c.sizes) {
      for (float v : {size.height_m, size.length_m, size.width_m}) w.Pod<float>(v);
    }
  }
  return w.Take();
}

ShapeModel DecodeShapeModel(std::string_view bytes) {
  Reader r(bytes);
  for (std::size_t i = 0; i + 1 < sizeof kMagic; ++i) {
    if (r.Pod<char>() != kMagic[i]) Reader::Fail("wrong magic");
  }
  const char version = r.Pod<char>();
  if (version != '1' && version != '2') Reader::Fail("wrong magic");
  ShapeModel m;
  auto& p = m.params;
  for (double* v : {&p.voxel_m, &p.normal_radius_m, &p.boundary_angle_rad, &p.keypoint_spacing_m, &p.shot_radius_m,
                    &p.sphere_radius_m, &p.detection_spacing_m, &p.accept_fraction, &p.merge_distance_m}) {
    *v = r.Pod<double>();
  }
  for (int* v : {&p.codebook_size, &p.activated_words, &p.azimuth_bins, &p.polar_bins, &p.max_keypoints}) {
    *v = r.Pod<std::int32_t>();
  }
  p.seed = r.Pod<std::uint64_t>();
  if (version == '1') {
    p.size_weight = 0;
  } else {
    for (double* v : {&p.size_weight, &p.size_bandwidth, &p.size_floor}) *v = r.Pod<double>();
  }
  try {
    CheckShapeModelParams(p);
  } catch (const Error& e) {
    Reader::Fail(std::string("parameters out of range (") + e.what() + ")");
  }
  m.descriptor_dims = r.Pod<std::int32_t>();
  if (m.descriptor_dims < 1 || m.descriptor_dims > 4096) Reader::Fail("descriptor length");
  const auto n = r.Count();
  if (n != static_cast<std::uint64_t>(p.codebook_size) * static_cast<std::uint64_t>(m.descriptor_dims)) {
    Reader::Fail("codebook size");
  }
  m.codebook.resize(n);
  for (auto& v : m.codebook) v = r.Pod<float>();
  const int bins = p.azimuth_bins * p.polar_bins;
  for (auto k = r.Count(); k > 0; --k) {
    CategoryModel c;
    c.name = r.Str();
    c.samples = r.Pod<std::int32_t>();
    c.keypoints = r.Pod<std::int32_t>();
    if (r.Count() != static_cast<std::uint32_t>(p.codebook_size)) Reader::Fail("category word count");
    c.words.resize(p.codebook_size);
    for (auto& word : c.words) {
      word.resize(r.Count());
      for (auto& b : word) {
        b.bin = r.Pod<std::int32_t>();
        b.weight = r.Pod<float>();
        if (b.bin < 0 || b.bin >= bins) Reader::Fail("vote bin out of range");
      }
    }
    if (version != '1') {
      c.sizes.resize(r.Count());
      for (auto& size : c.sizes) {
        for (float* v : {&size.height_m, &size.length_m, &size.width_m}) {
          *v = r.Pod<float>();
          if (!std::isfinite(*v) || *v < 0) Reader::Fail("size out of range");
        }
      }
    }
    m.categories.push_back(std::move(c));
  }
  if (m.categories.empty()) Reader::Fail("no category");
  if (!r.AtEnd()) Reader::Fail("trailing bytes");
  return m;
}

}  // namespace anchordb::engine
