#pragma once
// The codecs of the documents the built-in jobs store (storage/document_codec.h): a forgetting job's request and
// report, a backup job's request and report. Their records are storage's own (forget_policy.h, forgetting.h,
// backup.h). `what` names the row in errors.
#include <string>
#include <string_view>

#include "storage/backup.h"
#include "storage/forget_policy.h"
#include "storage/forgetting.h"

namespace anchordb::storage {

std::string EncodeForgetRequest(const ForgetRequest& request);
ForgetRequest DecodeForgetRequest(std::string_view stored, const std::string& what);
std::string EncodeForgetReport(const ForgetReport& report);
ForgetReport DecodeForgetReport(std::string_view stored, const std::string& what);

struct BackupJobRequest {
  std::string file;  // the copy to write (in the server's backup_dir)
};
std::string EncodeBackupRequest(const BackupJobRequest& request);
BackupJobRequest DecodeBackupRequest(std::string_view stored, const std::string& what);
std::string EncodeBackupReport(const BackupReport& report);
BackupReport DecodeBackupReport(std::string_view stored, const std::string& what);

}  // namespace anchordb::storage
