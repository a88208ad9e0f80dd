// The options library (host_tools/options, namespace rockwatch::options: the option declarations, defaults, ranges
// and help texts that `rockwatch` and rockwatch-monitor share) as the tool's commands use it: its names visible
// unqualified inside rockwatch::cli (namespace composition), so a command writes `given(app, "--r")` or
// `throw UsageError(...)` whichever library a name comes from. Included by every file of the tool that includes an
// options header; the monitor, which is not part of the tool, writes options:: instead.
#pragma once

namespace rockwatch::options {}

namespace rockwatch::cli {
using namespace rockwatch::options;
}  // namespace rockwatch::cli
