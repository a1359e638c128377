#include "storage/document_codec.h"

#include <cstring>
#include <limits>

#include "schema/error.h"
#include "storage/blob_codec.h"

namespace anchordb::storage {
namespace {

template <typename T>
void Append(std::string& out, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));  // little-endian machines only (blob_codec.h)
  out.append(b, sizeof(T));
}

}  // namespace

DocumentWriter::DocumentWriter(DocumentKind kind, std::uint16_t version) {
  Append(payload_, static_cast<std::uint16_t>(kind));
  Append(payload_, version);
}

DocumentWriter& DocumentWriter::Bool(bool v) { return Append(payload_, static_cast<std::uint8_t>(v ? 1 : 0)), *this; }
DocumentWriter& DocumentWriter::Int(std::int64_t v) { return Append(payload_, v), *this; }
DocumentWriter& DocumentWriter::Real(double v) { return Append(payload_, v), *this; }
DocumentWriter& DocumentWriter::Count(std::size_t n) { return Append(payload_, static_cast<std::uint32_t>(n)), *this; }

DocumentWriter& DocumentWriter::Text(std::string_view v) {
  Count(v.size());
  payload_.append(v);
  return *this;
}

DocumentWriter& DocumentWriter::Ints(const std::vector<std::int64_t>& v) {
  Count(v.size());
  for (std::int64_t x : v) Int(x);
  return *this;
}

DocumentWriter& DocumentWriter::Reals(const std::vector<double>& v) {
  Count(v.size());
  for (double x : v) Real(x);
  return *this;
}

DocumentWriter& DocumentWriter::Texts(const std::vector<std::string>& v) {
  Count(v.size());
  for (const std::string& x : v) Text(x);
  return *this;
}

std::string DocumentWriter::Finish() const {
  return EncodeBlob(BlobElement::kU8, {static_cast<std::uint32_t>(payload_.size())}, payload_);
}

bool IsEncodedDocument(std::string_view stored) { return stored.size() >= 4 && stored.substr(0, 4) == "ADBB"; }

DocumentReader::DocumentReader(std::string_view stored, DocumentKind kind, std::uint16_t newest_version,
                               std::string what)
    : what_(std::move(what)) {
  if (!IsEncodedDocument(stored)) Corrupt("it is not an encoded document");
  DecodedBlob blob;
  try {
    blob = DecodeBlob(stored);
  } catch (const Error& e) {
    Corrupt(e.what());
  }
  if (blob.element != BlobElement::kU8 || blob.shape.size() != 1) Corrupt("its envelope is not a byte string");
  payload_ = std::move(blob.bytes);
  std::uint16_t stored_kind = 0;
  std::memcpy(&stored_kind, Take(2), 2);
  std::memcpy(&version_, Take(2), 2);
  if (stored_kind != static_cast<std::uint16_t>(kind)) {
    Corrupt("it is a document of kind " + std::to_string(stored_kind) + ", not " +
            std::to_string(static_cast<std::uint16_t>(kind)));
  }
  if (version_ == 0 || version_ > newest_version) {
    Corrupt("its codec version " + std::to_string(version_) + " is not one this build reads (1.." +
            std::to_string(newest_version) + ")");
  }
}

void DocumentReader::Corrupt(const std::string& why) const {
  throw Error(ErrorCode::kInternal, "the stored document of " + what_ + " cannot be read: " + why);
}

const char* DocumentReader::Take(std::size_t n) {
  if (n > payload_.size() - pos_) Corrupt("it ends early (at byte " + std::to_string(pos_) + ")");
  const char* at = payload_.data() + pos_;
  pos_ += n;
  return at;
}

bool DocumentReader::Bool() {
  const auto v = static_cast<std::uint8_t>(*Take(1));
  if (v > 1) Corrupt("a boolean holds " + std::to_string(v));
  return v == 1;
}

std::int64_t DocumentReader::Int() {
  std::int64_t v;
  std::memcpy(&v, Take(8), 8);
  return v;
}

int DocumentReader::SmallInt() {
  const std::int64_t v = Int();
  if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max()) {
    Corrupt("a small integer holds " + std::to_string(v));
  }
  return static_cast<int>(v);
}

double DocumentReader::Real() {
  double v;
  std::memcpy(&v, Take(8), 8);
  return v;
}

std::size_t DocumentReader::Count() {
  std::uint32_t n;
  std::memcpy(&n, Take(4), 4);
  if (n > payload_.size() - pos_) Corrupt("a list of " + std::to_string(n) + " items is longer than the rest");
  return n;
}

std::string DocumentReader::Text() {
  const std::size_t n = Count();
  return std::string(Take(n), n);
}

std::vector<std::int64_t> DocumentReader::Ints() {
  std::vector<std::int64_t> out(Count());
  for (auto& x : out) x = Int();
  return out;
}

std::vector<double> DocumentReader::Reals() {
  std::vector<double> out(Count());
  for (auto& x : out) x = Real();
  return out;
}

std::vector<std::string> DocumentReader::Texts() {
  std::vector<std::string> out(Count());
  for (auto& x : out) x = Text();
  return out;
}

std::optional<std::int64_t> DocumentReader::OptionalInt() {
  return Bool() ? std::optional<std::int64_t>(Int()) : std::nullopt;
}
std::optional<double> DocumentReader::OptionalReal() { return Bool() ? std::optional<double>(Real()) : std::nullopt; }
std::optional<std::string> DocumentReader::OptionalText() {
  return Bool() ? std::optional<std::string>(Text()) : std::nullopt;
}

void DocumentReader::End() const {
  if (pos_ != payload_.size()) {
    Corrupt(std::to_string(payload_.size() - pos_) + " bytes are left after the fields of version " +
            std::to_string(version_));
  }
}

}  // namespace anchordb::storage
