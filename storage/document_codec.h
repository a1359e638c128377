#pragma once
// The stored form of a typed document (a job's request and result, a trained model's options and report): the
// blob envelope of storage/blob_codec.h (u8, one dimension, zstd) around a payload that starts with the document's
// kind and codec version (u16 each) and holds its fields in a fixed order, little-endian, each list preceded by its
// length. Each document's field order is written once, in its codec (storage/*_documents.cc); a decoder reads the
// versions it knows. Reading past the end, a wrong kind, an unknown version or bytes left over throw
// Error(kInternal) naming the document: a corrupt row is reported, never misread.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace anchordb::storage {

// One value per document; never reused (a stored row keeps its kind).
enum class DocumentKind : std::uint16_t {
  kForgetRequest = 1,
  kForgetReport = 2,
  kBackupRequest = 3,
  kBackupReport = 4,
  kCodebookRequest = 5,
  kCodebookResult = 6,
  kSegmentationRequest = 7,
  kSegmentationResult = 8,
  kShapeTrainingRequest = 9,
  kShapeTrainingResult = 10,
  kShapeModelReport = 11,
  kClassifierTrainingRequest = 12,
  kClassifierTrainingResult = 13,
  kClassifierReport = 14,
  kClassifierOptions = 15,
  kShapeModelOptions = 16,
};

class DocumentWriter {
 public:
  DocumentWriter(DocumentKind kind, std::uint16_t version);
  DocumentWriter& Bool(bool v);
  DocumentWriter& Int(std::int64_t v);
  DocumentWriter& Real(double v);
  DocumentWriter& Text(std::string_view v);
  DocumentWriter& Count(std::size_t n);  // a list's length, before its items
  DocumentWriter& Ints(const std::vector<std::int64_t>& v);
  DocumentWriter& Reals(const std::vector<double>& v);
  DocumentWriter& Texts(const std::vector<std::string>& v);
  template <typename T>
  DocumentWriter& Optional(const std::optional<T>& v) {
    Bool(v.has_value());
    if (v) Put(*v);
    return *this;
  }
  // The enveloped bytes to store.
  std::string Finish() const;

 private:
  void Put(bool v) { Bool(v); }
  void Put(std::int64_t v) { Int(v); }
  void Put(double v) { Real(v); }
  void Put(const std::string& v) { Text(v); }
  std::string payload_;
};

class DocumentReader {
 public:
  // `what` names the row in errors ("job 12's request"). Throws when `stored` is not a document of `kind` or its
  // version is above `newest_version`.
  DocumentReader(std::string_view stored, DocumentKind kind, std::uint16_t newest_version, std::string what);
  std::uint16_t version() const { return version_; }
  bool Bool();
  std::int64_t Int();
  int SmallInt();  // an Int that fits an int
  double Real();
  std::string Text();
  std::size_t Count();  // a list's length; at most the bytes left (every item takes one byte or more)
  std::vector<std::int64_t> Ints();
  std::vector<double> Reals();
  std::vector<std::string> Texts();
  std::optional<std::int64_t> OptionalInt();
  std::optional<double> OptionalReal();
  std::optional<std::string> OptionalText();
  // Throws when bytes are left: the document is longer than its version's fields.
  void End() const;

 private:
  [[noreturn]] void Corrupt(const std::string& why) const;
  const char* Take(std::size_t n);
  std::string payload_;
  std::size_t pos_ = 0;
  std::uint16_t version_ = 0;
  std::string what_;
};

// True when `stored` starts like a document (the blob envelope's magic): rows written before the documents were
// typed hold JSON text instead.
bool IsEncodedDocument(std::string_view stored);

// A document as read from its row: `encoded` (above) for rows written since the migration that typed it (0024: jobs,
// 0027: trained models' options and reports); rows written before hold the JSON text an earlier version wrote
// instead, kept as it was in `legacy_json` for the HTTP edge to show. Services never decode an old row's document:
// its job ran (or was marked failed) before the upgrade, and a model's report is only shown.
struct StoredDocument {
  std::string encoded;
  std::string legacy_json;
};

}  // namespace anchordb::storage
