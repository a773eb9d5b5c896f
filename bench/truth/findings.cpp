#include "bench/truth/findings.h"

namespace omnishadow::bench {

std::string_view to_string(Status s) {
  switch (s) {
    case Status::ok:
      return "ok";
    case Status::failed_quality:
      return "failed_quality";
    case Status::failed_check:
      return "failed_check";
    case Status::interrupted:
      return "interrupted";
    case Status::resource_error:
      return "resource_error";
    case Status::failed:
      return "failed";
    case Status::crashed:
      return "crashed";
    case Status::unsupported:
      return "unsupported";
  }
  return "?";
}

bool fails_run(Status s) {
  return s == Status::failed_quality || s == Status::failed_check || s == Status::resource_error ||
         s == Status::failed || s == Status::crashed;
}

void CaseFindings::add(Finding finding) {
  if (static_cast<int>(finding.status) > static_cast<int>(status)) status = finding.status;
  reason += (reason.empty() ? "" : "; ") + finding.message;
  findings.push_back(std::move(finding));
}

}  // namespace omnishadow::bench
