// ResultsReader: the read side of run.h5 (docs/output-format.md).
#include "talus/io/results.hpp"

#include "hdf5_util.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

namespace talus {

namespace {

using h5::Handle;
using h5::Site;

std::filesystem::path file_name(hid_t file) {
  const ssize_t len = H5Fget_name(file, nullptr, 0);
  if (len <= 0)
    return "run.h5";
  std::string name(static_cast<std::size_t>(len) + 1, '\0');
  H5Fget_name(file, name.data(), name.size());
  name.resize(static_cast<std::size_t>(len));
  return name;
}

bool link_exists(hid_t loc, const std::string& path, const std::filesystem::path& file) {
  // H5Lexists needs every intermediate group to exist; check them one by one.
  std::string prefix;
  std::size_t pos = 0;
  while (pos != std::string::npos) {
    const std::size_t next = path.find('/', pos + 1);
    prefix = path.substr(0, next);
    if (prefix.empty() || prefix == "/") {
      pos = next;
      continue;
    }
    const htri_t e = H5Lexists(loc, prefix.c_str(), H5P_DEFAULT);
    h5::check_status(e < 0 ? -1 : 0, "H5Lexists", prefix, file);
    if (e == 0)
      return false;
    pos = next;
  }
  return true;
}

} // namespace

ResultsReader::ResultsReader(const std::filesystem::path& h5_file) {
  h5::quiet();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(h5_file, ec))
    throw std::runtime_error("cannot read results file '" + h5_file.string() + "': no such file");
  const htri_t is_h5 = H5Fis_hdf5(h5_file.c_str());
  if (is_h5 <= 0)
    throw std::runtime_error("cannot read results file '" + h5_file.string() +
                             "': not an HDF5 file");
  Handle f = h5::file_handle(H5Fopen(h5_file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT),
                             Site{h5_file, "/"}, "H5Fopen (read-only)");
  if (!link_exists(f.get(), "/frames", h5_file) || !link_exists(f.get(), "/metadata", h5_file))
    throw std::runtime_error("'" + h5_file.string() +
                             "' is not a Talus results file (no /frames or /metadata group)");
  file_ = static_cast<long long>(f.get());
  // Ownership moves to file_; the destructor closes it.
  (void)f.release();
}

ResultsReader::~ResultsReader() {
  if (file_ >= 0)
    H5Fclose(static_cast<hid_t>(file_));
}

Index ResultsReader::frame_count() const {
  const auto fid = static_cast<hid_t>(file_);
  const auto path = file_name(fid);
  Index n = 0;
  for (;;) {
    const std::string g = h5::frame_group_name(n);
    const htri_t e = H5Lexists(fid, g.c_str(), H5P_DEFAULT);
    h5::check_status(e < 0 ? -1 : 0, "H5Lexists", g, path);
    if (e == 0)
      return n;
    ++n;
  }
}

namespace {

Handle open_frame(hid_t fid, Index frame, Index count) {
  const auto path = file_name(fid);
  if (frame < 0 || frame >= count)
    throw std::runtime_error(fmt::format("frame {} is not in '{}' (it has {} frame{})", frame,
                                         path.string(), count, count == 1 ? "" : "s"));
  const std::string g = h5::frame_group_name(frame);
  return h5::group_handle(H5Gopen2(fid, g.c_str(), H5P_DEFAULT), Site{path, g}, "H5Gopen2");
}

template <class T>
T read_scalar_attribute(hid_t obj, const char* name, hid_t mem_type, const std::string& object,
                        const std::filesystem::path& path) {
  const Site s{path, object + "@" + name};
  Handle a = h5::attribute_handle(H5Aopen(obj, name, H5P_DEFAULT), s, "H5Aopen");
  T value{};
  h5::check_status(H5Aread(a.get(), mem_type, &value), "H5Aread", s.object, path);
  return value;
}

} // namespace

double ResultsReader::frame_time(Index frame) const {
  const auto fid = static_cast<hid_t>(file_);
  Handle g = open_frame(fid, frame, frame_count());
  return read_scalar_attribute<double>(g.get(), "time", H5T_NATIVE_DOUBLE,
                                       h5::frame_group_name(frame), file_name(fid));
}

Index ResultsReader::frame_step(Index frame) const {
  const auto fid = static_cast<hid_t>(file_);
  Handle g = open_frame(fid, frame, frame_count());
  return read_scalar_attribute<std::int64_t>(g.get(), "step", H5T_NATIVE_INT64,
                                             h5::frame_group_name(frame), file_name(fid));
}

std::vector<std::string> ResultsReader::frame_fields(Index frame) const {
  const auto fid = static_cast<hid_t>(file_);
  Handle g = open_frame(fid, frame, frame_count());
  struct Names {
    std::vector<std::string> names;
    hid_t group;
  } names{{}, g.get()};
  auto cb = [](hid_t group, const char* name, const H5L_info_t*, void* data) -> herr_t {
    auto* n = static_cast<Names*>(data);
    H5O_info_t info;
    if (H5Oget_info_by_name2(group, name, &info, H5O_INFO_BASIC, H5P_DEFAULT) < 0)
      return -1;
    if (info.type == H5O_TYPE_DATASET)
      n->names.emplace_back(name);
    return 0;
  };
  // Creation order (position first, then the fields in the documented order) where the group
  // tracks it; name order otherwise.
  hsize_t idx = 0;
  herr_t st = H5Literate(g.get(), H5_INDEX_CRT_ORDER, H5_ITER_INC, &idx, cb, &names);
  if (st < 0) {
    names.names.clear();
    idx = 0;
    st = H5Literate(g.get(), H5_INDEX_NAME, H5_ITER_INC, &idx, cb, &names);
  }
  h5::check_status(st, "H5Literate", h5::frame_group_name(frame), file_name(fid));
  return names.names;
}

bool ResultsReader::frame_has(Index frame, const std::string& path) const {
  const auto fid = static_cast<hid_t>(file_);
  Handle g = open_frame(fid, frame, frame_count());
  if (path.empty() || path.front() == '/' || path.back() == '/')
    return false;
  return link_exists(fid, h5::frame_group_name(frame) + "/" + path, file_name(fid));
}

std::vector<double> ResultsReader::read(Index frame, const std::string& field, Index* rows,
                                        Index* cols) const {
  const auto fid = static_cast<hid_t>(file_);
  const auto path = file_name(fid);
  Handle g = open_frame(fid, frame, frame_count());
  const std::string object = h5::frame_group_name(frame) + "/" + field;
  if (!frame_has(frame, field))
    throw std::runtime_error(
        fmt::format("field '{}' is not in frame {} of '{}'", field, frame, path.string()));
  const Site s{path, object};
  Handle d = h5::dataset_handle(H5Dopen2(g.get(), field.c_str(), H5P_DEFAULT), s, "H5Dopen2");
  Handle type = h5::type_handle(H5Dget_type(d.get()), s, "H5Dget_type");
  const H5T_class_t cls = H5Tget_class(type.get());
  if (cls != H5T_FLOAT && cls != H5T_INTEGER)
    throw std::runtime_error("'" + object + "' in '" + path.string() + "' is not numeric");
  Handle space = h5::space_handle(H5Dget_space(d.get()), s, "H5Dget_space");
  const int rank = H5Sget_simple_extent_ndims(space.get());
  h5::check_status(rank, "H5Sget_simple_extent_ndims", object, path);
  // Rank > 2 (the lattice-shaped grid/ datasets): the leading dimensions fold into rows.
  std::vector<hsize_t> dims(static_cast<std::size_t>(std::max(rank, 1)), 1);
  if (rank > 0)
    h5::check_status(H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr),
                     "H5Sget_simple_extent_dims", object, path);
  Index r = 1;
  for (std::size_t d = 0; d + 1 < dims.size(); ++d)
    r *= static_cast<Index>(dims[d]);
  const Index c = rank >= 2 ? static_cast<Index>(dims.back()) : 1;
  if (rank < 2)
    r = static_cast<Index>(dims[0]);
  std::vector<double> out(static_cast<std::size_t>(r * c));
  if (!out.empty())
    h5::check_status(H5Dread(d.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()),
                     "H5Dread", object, path);
  if (rows)
    *rows = r;
  if (cols)
    *cols = c;
  return out;
}

std::string ResultsReader::case_text() const {
  const auto fid = static_cast<hid_t>(file_);
  const auto path = file_name(fid);
  const Site s{path, "/metadata/case_text"};
  if (!link_exists(fid, s.object, path))
    throw std::runtime_error("'" + path.string() + "' has no /metadata/case_text");
  Handle d = h5::dataset_handle(H5Dopen2(fid, "/metadata/case_text", H5P_DEFAULT), s, "H5Dopen2");
  return h5::read_string(d.get(), false, s);
}

std::string ResultsReader::metadata_string(const std::string& name) const {
  return attribute_string("/metadata", name);
}

std::string ResultsReader::frame_attribute(Index frame, const std::string& group,
                                           const std::string& name) const {
  return attribute_string(h5::frame_group_name(frame) + "/" + group, name);
}

std::string ResultsReader::attribute_string(const std::string& group,
                                            const std::string& name) const {
  const auto fid = static_cast<hid_t>(file_);
  const auto path = file_name(fid);
  const Site s{path, group + "@" + name};
  Handle g =
      h5::group_handle(H5Gopen2(fid, group.c_str(), H5P_DEFAULT), Site{path, group}, "H5Gopen2");
  const htri_t e = H5Aexists(g.get(), name.c_str());
  h5::check_status(e < 0 ? -1 : 0, "H5Aexists", s.object, path);
  if (e == 0)
    throw std::runtime_error("attribute '" + name + "' is not in '" + path.string() + ":" + group +
                             "'");
  Handle a = h5::attribute_handle(H5Aopen(g.get(), name.c_str(), H5P_DEFAULT), s, "H5Aopen");
  Handle type = h5::type_handle(H5Aget_type(a.get()), s, "H5Aget_type");
  const H5T_class_t cls = H5Tget_class(type.get());
  if (cls == H5T_STRING)
    return h5::read_string(a.get(), true, s);
  if (cls != H5T_INTEGER && cls != H5T_FLOAT)
    throw std::runtime_error("attribute '" + name + "' in '" + path.string() + ":" + group +
                             "' is neither text nor a number");
  // Numbers are returned as text: integers as such, doubles in shortest round-trip form, array
  // entries separated by single spaces.
  Handle space = h5::space_handle(H5Aget_space(a.get()), s, "H5Aget_space");
  const hssize_t n = H5Sget_simple_extent_npoints(space.get());
  h5::check_status(n < 0 ? -1 : 0, "H5Sget_simple_extent_npoints", s.object, path);
  std::string out;
  if (cls == H5T_INTEGER) {
    std::vector<long long> v(static_cast<std::size_t>(n));
    h5::check_status(H5Aread(a.get(), H5T_NATIVE_LLONG, v.data()), "H5Aread", s.object, path);
    for (std::size_t i = 0; i < v.size(); ++i)
      out += (i ? " " : "") + std::to_string(v[i]);
  } else {
    std::vector<double> v(static_cast<std::size_t>(n));
    h5::check_status(H5Aread(a.get(), H5T_NATIVE_DOUBLE, v.data()), "H5Aread", s.object, path);
    for (std::size_t i = 0; i < v.size(); ++i)
      out += (i ? " " : "") + fmt::format("{}", v[i]);
  }
  return out;
}

} // namespace talus
