// The stored documents of the jobs table (services/jobs/job_documents.h): a backup job's request reads back the file
// it was written with, and a request that names no file is refused with the field, changing nothing.
#include "services/jobs/job_documents.h"

#include <gtest/gtest.h>

#include "schema/error.h"

namespace anchordb::services {
namespace {

TEST(JobDocumentsTest, ABackupRequestReadsBackItsFile) {
  for (const std::string file : {"/var/lib/anchordb/backups/home-20261207T034500Z.sqlite", "with \"quotes\" and ü.db"}) {
    EXPECT_EQ(BackupFileFromDocument(BackupRequestDocument(file)), file);
  }
}

TEST(JobDocumentsTest, ABackupRequestWithoutAFileIsRefusedNamingTheField) {
  for (const char* text : {"", "{}", "[\"/a.db\"]", "{\"file\": 3}", "{\"file\": null}", "{\"fil\": \"/a.db\"}"}) {
    try {
      BackupFileFromDocument(text);
      ADD_FAILURE() << "read a file from " << text;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument) << text;
      EXPECT_EQ(e.field(), "file") << text;
    }
  }
}

}  // namespace
}  // namespace anchordb::services
