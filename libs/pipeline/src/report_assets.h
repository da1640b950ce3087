// The report page's static files, embedded in the binary at build time from
// libs/pipeline/report/ (generated report_assets.cc; see CMakeLists.txt), so
// `hmt-slam run --report` needs nothing beside the executable.
#pragma once

namespace hmt::pipeline::report_assets {

extern const char kIndexHtml[];
extern const char kReportJs[];
extern const char kReportCss[];

}  // namespace hmt::pipeline::report_assets
