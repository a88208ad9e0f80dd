// The dashboard's web page, compiled into the binary (host_tools/cmake/embed_dashboard_assets.cmake): the page, its
// script and style from host_tools/rockwatch/dashboard/web/, and uPlot's files from node_modules/uplot/dist/ as
// `npm ci` installed them (scripts/install-deps.sh). The installed `rockwatch` serves them without the source tree,
// an npm registry or the internet. When node_modules was missing at build time the uPlot entries are there but not
// present: the dashboard says so at start and the page shows its values without the charts.
#pragma once

#include <cstddef>

namespace rockwatch::cli {

struct EmbeddedAsset {
  const char* path;            // URL path, e.g. "/app.js"; nullptr ends the table
  const char* content_type;    // "text/javascript; charset=utf-8", ...
  const unsigned char* bytes;  // the file's bytes (`size` of them)
  std::size_t size;
  bool present;                // false: the file was missing at build time (bytes empty)
  const char* source;          // where it came from, for the message when it is missing
};

// Every asset, ended by an entry whose path is nullptr. Defined in the generated source.
const EmbeddedAsset* embedded_dashboard_assets();

}  // namespace rockwatch::cli
