#include "spectrum_plot.hpp"

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <vector>

#include "option_values.hpp"
#include "rockwatch/core/design_spectrum.hpp"

namespace rockwatch::cli {

namespace {

// mkdtemp: a directory only this process can use, whatever else runs in the temporary directory.
class PrivateDirectory {
 public:
  PrivateDirectory() {
    std::error_code ec;
    const std::filesystem::path base = std::filesystem::temp_directory_path(ec);
    const std::string pattern = ((ec ? std::filesystem::path("/tmp") : base) / "rockwatch_spectrum.XXXXXX").string();
    std::vector<char> buffer(pattern.begin(), pattern.end());
    buffer.push_back('\0');
    if (mkdtemp(buffer.data()) == nullptr) {
      error_ = std::string("cannot create a temporary directory: ") + std::strerror(errno);
      return;
    }
    path_ = buffer.data();
  }
  ~PrivateDirectory() {
    if (path_.empty()) return;
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  PrivateDirectory(const PrivateDirectory&) = delete;
  PrivateDirectory& operator=(const PrivateDirectory&) = delete;

  bool ok() const { return !path_.empty(); }
  const std::string& error() const { return error_; }
  std::string file(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
  std::string error_;
};

std::string file_name(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

std::string plot_title(const SpectrumRequest& q, const SpectrumResult& r) {
  std::string title = file_name(r.record.path) + ": elastic response spectrum, damping " +
                      number_text(100.0 * q.damping) + " %";
  if (!r.record.description.empty()) {
    std::string description = r.record.description;
    for (char& c : description) {
      if (static_cast<unsigned char>(c) < 0x20) c = ' ';
    }
    if (description.size() > 90) description = description.substr(0, 87) + "...";
    title += "\n" + description;
  }
  return title;
}

std::string target_label(const SpectrumTarget& t) {
  std::string label = "target " + std::string(core::spectrum_name(t.shape.kind)) + ", a_g = " + number_text(t.pga_g) + " g";
  if (t.shape.kind == core::SpectrumKind::npr9998_2015) {
    label += "\n(back-calculated from the paper's static results;\nNPR 9998:2015 parameters are not public)";
  }
  return label;
}

}  // namespace

PlotOutcome plot_spectrum(const SpectrumRequest& q, const SpectrumResult& r) {
  const std::string& png_path = *q.plot_path;
  std::error_code ec;
  std::filesystem::remove(png_path, ec);

  const PrivateDirectory scratch;
  if (!scratch.ok()) return {false, scratch.error()};
  const std::string csv_path = scratch.file("spectrum.csv");
  {
    std::ofstream csv(csv_path, std::ios::binary);
    write_spectrum_csv(csv, r);
    csv.close();
    if (!csv) return {false, "cannot write the plot data to " + csv_path};
  }
  std::vector<std::string> args{csv_path, png_path, plot_title(q, r), number_text(q.g_mps2())};
  if (q.target) args.push_back(target_label(*q.target));
  return run_plot_script("response_spectrum", args);
}

}  // namespace rockwatch::cli
