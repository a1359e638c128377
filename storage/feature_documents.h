#pragma once
// The documents of a codebook job (storage/document_codec.h): what it was asked and what it built.
#include <cstdint>
#include <string>
#include <string_view>

namespace anchordb::storage {

struct CodebookJobRequest {
  std::string type;  // the feature type ("fpfh", ...)
  int words = 0;
  std::uint64_t seed = 0;
};

struct CodebookJobResult {
  std::string type;
  int words = 0;
  int dims = 0;
  std::int64_t features = 0;  // clustered
  std::int64_t assigned = 0;  // given their codeword (also those stored while k-means ran)
};

std::string EncodeCodebookRequest(const CodebookJobRequest& request);
CodebookJobRequest DecodeCodebookRequest(std::string_view stored, const std::string& what);
std::string EncodeCodebookResult(const CodebookJobResult& result);
CodebookJobResult DecodeCodebookResult(std::string_view stored, const std::string& what);

}  // namespace anchordb::storage
