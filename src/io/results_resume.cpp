// ResultsWriter's resume: a run continued from a checkpoint keeps the frames the checkpoint
// names and writes the later ones again. A run.h5 that a kill left damaged while it wrote a
// later frame is rebuilt from the frames that still read. Layout: docs/output-format.md.
#include "talus/io/results.hpp"

#include "hdf5_util.hpp"

#include <filesystem>
#include <fmt/format.h>
#include <stdexcept>
#include <string>

namespace talus {

namespace {

using h5::Handle;
using h5::Site;

/// Deletes the frames from `first` on (those a resumed run writes again).
void delete_frames_from(const std::filesystem::path& f, Index first) {
  Handle file = h5::open_for_append(f);
  for (Index k = 0;; ++k) {
    const std::string gname = h5::frame_group_name(k);
    const htri_t exists = H5Lexists(file.get(), gname.c_str(), H5P_DEFAULT);
    h5::check_status(exists < 0 ? -1 : 0, "H5Lexists", gname, f);
    if (k < first) {
      if (exists == 0)
        throw std::runtime_error(
            fmt::format("'{}' lacks frame {} that the checkpoint names", f.string(), k));
    } else if (exists > 0) {
      h5::check_status(H5Ldelete(file.get(), gname.c_str(), H5P_DEFAULT), "H5Ldelete", gname, f);
    } else {
      break;
    }
  }
  h5::check_status(file.close(), "H5Fclose", "", f);
}

/// Opens `f` read-only. A file that a kill cut short of the end its superblock records
/// (HDF5: "truncated file: eof = ..., stored_eof = N") is first padded with zeros to N: what
/// was lost belongs to the frame being written, which the caller leaves out.
Handle open_cut_short(const std::filesystem::path& f) {
  try {
    return h5::file_handle(H5Fopen(f.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), Site{f, "/"},
                           "H5Fopen (read-only)");
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    const std::size_t at = what.find("stored_eof = ");
    if (what.find("truncated file") == std::string::npos || at == std::string::npos)
      throw;
    const auto stored = std::stoull(what.substr(at + 13));
    if (stored <= std::filesystem::file_size(f))
      throw;
    std::filesystem::resize_file(f, stored);
    return h5::file_handle(H5Fopen(f.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), Site{f, "/"},
                           "H5Fopen (read-only)");
  }
}

/// Copies the metadata, the XDMF helpers and the first `frames` frames of `f` into a new
/// file renamed over it: for a run.h5 that a kill left damaged while it wrote a later frame
/// (HDF5 1.10 keeps no journal), whose earlier frames still read.
void rebuild_with_frames(const std::filesystem::path& f, Index frames) {
  const std::filesystem::path tmp = f.string() + ".rebuild";
  {
    Handle src = open_cut_short(f);
    Handle dst = h5::file_handle(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT),
                                 Site{tmp, "/"}, "H5Fcreate");
    const Site root{tmp, "/"};
    h5::write_string_attribute(dst.get(), "format", "talus-results", root);
    h5::write_int64_attribute(dst.get(), "format_version", 1, root);
    const auto copy = [&](const std::string& name) {
      h5::check_status(
          H5Ocopy(src.get(), name.c_str(), dst.get(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT),
          "H5Ocopy", name, f);
    };
    copy("/metadata");
    copy("/xdmf");
    {
      const Site s{tmp, "/frames"};
      Handle g = h5::group_handle(
          H5Gcreate2(dst.get(), "/frames", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), s, "H5Gcreate2");
      h5::write_string_attribute(g.get(), "time_units", "s", s);
    }
    for (Index k = 0; k < frames; ++k)
      copy(h5::frame_group_name(k));
    h5::check_status(dst.close(), "H5Fclose", "", tmp);
  }
  std::filesystem::rename(tmp, f);
}

} // namespace

ResultsWriter::ResultsWriter(std::filesystem::path dir, RunMetadata metadata,
                             std::vector<FrameRecord> kept)
    : dir_(std::move(dir)), h5_path_(dir_ / "run.h5"), xmf_path_(dir_ / "run.xmf"),
      metadata_(std::move(metadata)), frames_(static_cast<Index>(kept.size())),
      frame_info_(std::move(kept)) {
  h5::quiet();
  try {
    delete_frames_from(h5_path_, frames_);
  } catch (const std::runtime_error&) {
    rebuild_with_frames(h5_path_, frames_);
  }
  write_xdmf();
}

} // namespace talus
