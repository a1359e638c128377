// The typed documents of storage/document_codec.h and the built-in jobs' codecs (storage/job_documents.h): every
// field reads back as written, and a document that is truncated, longer than its version, of another kind, of a
// newer version, or not a document at all is refused with kInternal naming the row, never misread.
#include "storage/document_codec.h"

#include <gtest/gtest.h>

#include <limits>

#include "schema/error.h"
#include "storage/job_documents.h"

namespace anchordb::storage {
namespace document_codec_test {

std::string ReasonOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInternal);
    return e.what();
  }
  ADD_FAILURE() << "no error";
  return "";
}

TEST(DocumentCodecTest, EveryFieldReadsBackAsWritten) {
  const std::string stored = DocumentWriter(DocumentKind::kCodebookRequest, 3)
                                 .Bool(true)
                                 .Int(std::numeric_limits<std::int64_t>::min())
                                 .Real(-0.125)
                                 .Text(std::string("nul\0byte ü", 11))
                                 .Ints({1, -2, 3})
                                 .Reals({})
                                 .Texts({"a", ""})
                                 .Optional(std::optional<double>())
                                 .Optional(std::optional<std::int64_t>(7))
                                 .Finish();
  EXPECT_TRUE(IsEncodedDocument(stored));
  DocumentReader r(stored, DocumentKind::kCodebookRequest, 3, "row 1");
  EXPECT_EQ(r.version(), 3);
  EXPECT_TRUE(r.Bool());
  EXPECT_EQ(r.Int(), std::numeric_limits<std::int64_t>::min());
  EXPECT_EQ(r.Real(), -0.125);
  EXPECT_EQ(r.Text(), std::string("nul\0byte ü", 11));
  EXPECT_EQ(r.Ints(), (std::vector<std::int64_t>{1, -2, 3}));
  EXPECT_TRUE(r.Reals().empty());
  EXPECT_EQ(r.Texts(), (std::vector<std::string>{"a", ""}));
  EXPECT_FALSE(r.OptionalReal().has_value());
  EXPECT_EQ(r.OptionalInt(), std::optional<std::int64_t>(7));
  r.End();
}

TEST(DocumentCodecTest, ADocumentThatDoesNotMatchIsRefusedNamingTheRow) {
  const std::string stored = DocumentWriter(DocumentKind::kBackupRequest, 1).Text("/b/x.sqlite").Finish();
  EXPECT_NE(ReasonOf([&] { DocumentReader(stored, DocumentKind::kForgetRequest, 1, "job 9's request"); })
                .find("job 9's request"),
            std::string::npos);
  EXPECT_NE(ReasonOf([&] { DocumentReader(DocumentWriter(DocumentKind::kBackupRequest, 2).Finish(),
                                          DocumentKind::kBackupRequest, 1, "job 9"); })
                .find("version 2"),
            std::string::npos);
  EXPECT_NE(ReasonOf([&] { DocumentReader(R"({"file": "/b/x.sqlite"})", DocumentKind::kBackupRequest, 1, "job 9"); })
                .find("not an encoded document"),
            std::string::npos);
  // Read as more fields than it has: ends early; read as fewer: bytes left over.
  EXPECT_NE(ReasonOf([&] {
              DocumentReader r(stored, DocumentKind::kBackupRequest, 1, "job 9");
              r.Text();
              r.Int();
            }).find("ends early"),
            std::string::npos);
  EXPECT_NE(ReasonOf([&] { DocumentReader(stored, DocumentKind::kBackupRequest, 1, "job 9").End(); }).find("left"),
            std::string::npos);
  // A list length larger than the document cannot allocate: refused before reading.
  const std::string long_list = DocumentWriter(DocumentKind::kBackupRequest, 1).Count(1u << 30).Finish();
  EXPECT_NE(ReasonOf([&] { DocumentReader(long_list, DocumentKind::kBackupRequest, 1, "job 9").Ints(); })
                .find("longer than the rest"),
            std::string::npos);
  // A boolean other than 0 or 1.
  const std::string odd_bool = DocumentWriter(DocumentKind::kBackupRequest, 1).Int(2).Finish();
  EXPECT_NE(ReasonOf([&] { DocumentReader(odd_bool, DocumentKind::kBackupRequest, 1, "job 9").Bool(); })
                .find("boolean"),
            std::string::npos);
}

TEST(JobDocumentsTest, AForgetRequestAndReportReadBackWithEveryField) {
  ForgetRequest request;
  request.policy = {false, std::nullopt, 0.25, 3600.0, true};
  request.dry_run = true;
  request.now_ns = 1'700'000'000'000'000'000;
  const ForgetRequest back = DecodeForgetRequest(EncodeForgetRequest(request), "job 1");
  EXPECT_EQ(back.policy.drop_superseded, false);
  EXPECT_FALSE(back.policy.keyframe_max_age_s.has_value());
  EXPECT_EQ(back.policy.keep_relevance_at_least, 0.25);
  EXPECT_EQ(back.policy.event_max_age_s, std::optional<double>(3600.0));
  EXPECT_TRUE(back.policy.vacuum);
  EXPECT_TRUE(back.dry_run);
  EXPECT_EQ(back.now_ns, request.now_ns);

  ForgetReport report;
  report.map_id = "home";
  report.policy = request.policy;
  report.models_deleted = {4, 5};
  report.keyframes_deleted = {11};
  report.events_kept_pinned_instance = 6;
  report.freelist_after_vacuum = 42;
  report.vacuum_mode = "incremental";
  report.committed = true;
  report.seconds = 0.5;
  const ForgetReport r = DecodeForgetReport(EncodeForgetReport(report), "job 1");
  EXPECT_EQ(r.map_id, "home");
  EXPECT_EQ(r.models_deleted, report.models_deleted);
  EXPECT_EQ(r.keyframes_deleted, report.keyframes_deleted);
  EXPECT_TRUE(r.events_deleted.empty());
  EXPECT_EQ(r.events_kept_pinned_instance, 6);
  EXPECT_EQ(r.freelist_after_vacuum, 42);
  EXPECT_EQ(r.vacuum_mode, "incremental");
  EXPECT_TRUE(r.committed);
  EXPECT_EQ(r.seconds, 0.5);
  EXPECT_FALSE(r.policy.keyframe_max_age_s.has_value());
  // A report is not a request.
  ReasonOf([&] { DecodeForgetRequest(EncodeForgetReport(report), "job 1"); });
}

TEST(JobDocumentsTest, ABackupRequestAndReportReadBack) {
  for (const std::string file : {"/var/lib/anchordb/backups/home-20261207T034500Z.sqlite", "with \"quotes\" and ü.db"}) {
    EXPECT_EQ(DecodeBackupRequest(EncodeBackupRequest({file}), "job 2").file, file);
  }
  const BackupReport report{"/b/x.sqlite", 4096, 1, 2, "ok", 0.75};
  const BackupReport r = DecodeBackupReport(EncodeBackupReport(report), "job 2");
  EXPECT_EQ(r.file, report.file);
  EXPECT_EQ(r.bytes, 4096);
  EXPECT_EQ(r.pages, 1);
  EXPECT_EQ(r.restarts, 2);
  EXPECT_EQ(r.integrity, "ok");
  EXPECT_EQ(r.duration_s, 0.75);
}

}  // namespace
}  // namespace anchordb::storage
