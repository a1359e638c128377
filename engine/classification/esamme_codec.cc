// The E-SAMME model blob: "ESAM", u32 version, then the model's fields little-endian, strings length-prefixed; each
// round's base classifier as OpenCV FileStorage text (base_classifiers.cc).
#include <cstring>

#include "engine/classification/esamme.h"
#include "schema/error.h"

namespace anchordb::engine {
namespace {

constexpr char kMagic[4] = {'E', 'S', 'A', 'M'};
// 2 added BaseSetting::svm_gamma_per_dim (one byte after svm_gamma); version 1 blobs read with it false.
constexpr std::uint32_t kVersion = 2;
constexpr std::uint32_t kMaxCount = 1u << 24;

class Writer {
 public:
  template <typename T>
  void Pod(T v) {
    const auto* p = reinterpret_cast<const char*>(&v);
    out_.append(p, sizeof(T));
  }
  void Str(const std::string& s) {
    Pod<std::uint32_t>(static_cast<std::uint32_t>(s.size()));
    out_ += s;
  }
  void Floats(const Eigen::VectorXf& v) {
    Pod<std::uint32_t>(static_cast<std::uint32_t>(v.size()));
    out_.append(reinterpret_cast<const char*>(v.data()), static_cast<std::size_t>(v.size()) * sizeof(float));
  }
  std::string Take() { return std::move(out_); }

 private:
  std::string out_;
};

class Reader {
 public:
  explicit Reader(const std::string& in) : in_(in) {}
  template <typename T>
  T Pod() {
    Need(sizeof(T));
    T v;
    std::memcpy(&v, in_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return v;
  }
  std::uint32_t Count() {
    const auto c = Pod<std::uint32_t>();
    if (c > kMaxCount) Fail();
    return c;
  }
  std::string Str() {
    const auto len = Count();
    Need(len);
    std::string s = in_.substr(at_, len);
    at_ += len;
    return s;
  }
  Eigen::VectorXf Floats() {
    const auto len = Count();
    Need(static_cast<std::size_t>(len) * sizeof(float));
    Eigen::VectorXf v(len);
    std::memcpy(v.data(), in_.data() + at_, static_cast<std::size_t>(len) * sizeof(float));
    at_ += static_cast<std::size_t>(len) * sizeof(float);
    return v;
  }
  bool AtEnd() const { return at_ == in_.size(); }
  [[noreturn]] static void Fail() { throw Error(ErrorCode::kUnprocessable, "damaged E-SAMME model blob"); }

 private:
  void Need(std::size_t bytes) const {
    if (in_.size() - at_ < bytes) Fail();
  }
  const std::string& in_;
  std::size_t at_ = 0;
};

}  // namespace

std::string EncodeEsamme(const EsammeModel& m) {
  Writer w;
  for (char c : kMagic) w.Pod<char>(c);
  w.Pod<std::uint32_t>(kVersion);
  w.Pod<std::uint32_t>(static_cast<std::uint32_t>(m.class_names.size()));
  for (const auto& c : m.class_names) w.Str(c);
  w.Pod<std::uint32_t>(static_cast<std::uint32_t>(m.feature_types.size()));
  for (std::size_t t = 0; t < m.feature_types.size(); ++t) {
    w.Str(m.feature_types[t]);
    w.Pod<std::int32_t>(m.feature_dims[t]);
    w.Floats(m.scaling[t].mean);
    w.Floats(m.scaling[t].inv_std);
  }
  w.Pod<std::uint32_t>(static_cast<std::uint32_t>(m.settings.size()));
  for (const auto& s : m.settings) {
    w.Pod<std::uint8_t>(static_cast<std::uint8_t>(s.kind));
    w.Pod<double>(s.svm_c);
    w.Pod<double>(s.svm_gamma);
    w.Pod<std::uint8_t>(s.svm_gamma_per_dim ? 1 : 0);
    w.Pod<std::int32_t>(s.tree_max_depth);
    w.Pod<std::int32_t>(s.tree_min_samples);
    w.Pod<std::uint32_t>(static_cast<std::uint32_t>(s.mlp_hidden.size()));
    for (int h : s.mlp_hidden) w.Pod<std::int32_t>(h);
    w.Pod<std::int32_t>(s.mlp_iterations);
    w.Pod<std::int32_t>(s.knn_k);
  }
  w.Pod<std::uint8_t>(m.unknown ? 1 : 0);
  w.Pod<double>(m.unknown_min_share);
  w.Pod<std::uint32_t>(static_cast<std::uint32_t>(m.rounds.size()));
  for (const auto& r : m.rounds) {
    w.Pod<std::int32_t>(r.setting);
    w.Pod<std::int32_t>(r.feature_type);
    w.Pod<double>(r.error);
    w.Pod<double>(r.alpha);
    w.Str(r.classifier->Serialize());
  }
  return w.Take();
}

EsammeModel DecodeEsamme(const std::string& blob) {
  Reader r(blob);
  for (char c : kMagic) if (r.Pod<char>() != c) Reader::Fail();
  const std::uint32_t version = r.Pod<std::uint32_t>();
  if (version < 1 || version > kVersion) throw Error(ErrorCode::kUnprocessable, "unsupported E-SAMME model version");
  EsammeModel m;
  for (auto k = r.Count(); k > 0; --k) m.class_names.push_back(r.Str());
  for (auto t = r.Count(); t > 0; --t) {
    m.feature_types.push_back(r.Str());
    m.feature_dims.push_back(r.Pod<std::int32_t>());
    FeatureScaling s;
    s.mean = r.Floats();
    s.inv_std = r.Floats();
    if (s.mean.size() != m.feature_dims.back() || s.inv_std.size() != m.feature_dims.back()) Reader::Fail();
    m.scaling.push_back(std::move(s));
  }
  for (auto n = r.Count(); n > 0; --n) {
    BaseSetting s;
    const auto kind = r.Pod<std::uint8_t>();
    if (kind > static_cast<std::uint8_t>(BaseKind::kKnn)) Reader::Fail();
    s.kind = static_cast<BaseKind>(kind);
    s.svm_c = r.Pod<double>();
    s.svm_gamma = r.Pod<double>();
    if (version >= 2) {
      const auto per_dim = r.Pod<std::uint8_t>();
      if (per_dim > 1) Reader::Fail();
      s.svm_gamma_per_dim = per_dim == 1;
    }
    s.tree_max_depth = r.Pod<std::int32_t>();
    s.tree_min_samples = r.Pod<std::int32_t>();
    s.mlp_hidden.clear();
    for (auto h = r.Count(); h > 0; --h) s.mlp_hidden.push_back(r.Pod<std::int32_t>());
    s.mlp_iterations = r.Pod<std::int32_t>();
    s.knn_k = r.Pod<std::int32_t>();
    m.settings.push_back(std::move(s));
  }
  m.unknown = r.Pod<std::uint8_t>() != 0;
  m.unknown_min_share = r.Pod<double>();
  const int k = static_cast<int>(m.class_names.size());
  for (auto n = r.Count(); n > 0; --n) {
    EsammeRound round;
    round.setting = r.Pod<std::int32_t>();
    round.feature_type = r.Pod<std::int32_t>();
    round.error = r.Pod<double>();
    round.alpha = r.Pod<double>();
    if (round.setting < 0 || round.setting >= static_cast<int>(m.settings.size()) || round.feature_type < 0 ||
        round.feature_type >= static_cast<int>(m.feature_types.size())) {
      Reader::Fail();
    }
    round.classifier = LoadBaseClassifier(m.settings[static_cast<std::size_t>(round.setting)].kind, r.Str(), k);
    m.rounds.push_back(std::move(round));
  }
  if (!r.AtEnd() || k < 2) Reader::Fail();
  return m;
}

}  // namespace anchordb::engine
