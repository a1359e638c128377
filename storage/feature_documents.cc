#include "storage/feature_documents.h"

#include "storage/document_codec.h"

namespace anchordb::storage {
namespace {
constexpr std::uint16_t kCodebookVersion = 1;
}  // namespace

std::string EncodeCodebookRequest(const CodebookJobRequest& r) {
  return DocumentWriter(DocumentKind::kCodebookRequest, kCodebookVersion)
      .Text(r.type)
      .Int(r.words)
      .Int(static_cast<std::int64_t>(r.seed))
      .Finish();
}

CodebookJobRequest DecodeCodebookRequest(std::string_view stored, const std::string& what) {
  DocumentReader d(stored, DocumentKind::kCodebookRequest, kCodebookVersion, what);
  CodebookJobRequest r;
  r.type = d.Text();
  r.words = d.SmallInt();
  r.seed = static_cast<std::uint64_t>(d.Int());
  d.End();
  return r;
}

std::string EncodeCodebookResult(const CodebookJobResult& r) {
  return DocumentWriter(DocumentKind::kCodebookResult, kCodebookVersion)
      .Text(r.type)
      .Int(r.words)
      .Int(r.dims)
      .Int(r.features)
      .Int(r.assigned)
      .Finish();
}

CodebookJobResult DecodeCodebookResult(std::string_view stored, const std::string& what) {
  DocumentReader d(stored, DocumentKind::kCodebookResult, kCodebookVersion, what);
  CodebookJobResult r;
  r.type = d.Text();
  r.words = d.SmallInt();
  r.dims = d.SmallInt();
  r.features = d.Int();
  r.assigned = d.Int();
  d.End();
  return r;
}

}  // namespace anchordb::storage
