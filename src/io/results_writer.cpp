// ResultsWriter: run.h5 (metadata + one group per frame). The file is opened and closed around
// every frame so that an interrupted run keeps every complete frame; run.xmf is rewritten
// after each frame (xdmf.cpp). Layout: docs/output-format.md.
#include "talus/io/results.hpp"

#include "hdf5_util.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <functional>
#include <stdexcept>
#include <string>
#include <system_error>

namespace talus {

namespace {

using h5::Handle;
using h5::Site;

std::string join_lines(const std::vector<std::string>& items) {
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (i)
      out += '\n';
    out += items[i];
  }
  return out;
}

void set_dataset_attributes(hid_t dset, const h5::DatasetInfo& info, const Site& s) {
  h5::write_string_attribute(dset, "units", info.units, s);
  h5::write_string_attribute(dset, "description", info.description, s);
}

/// Writes a dataset of the given dimensions from row-major data.
template <class T>
void write_array(hid_t group, const std::string& group_name, const h5::DatasetInfo& info,
                 const std::vector<hsize_t>& dims, const std::vector<T>& data,
                 const std::filesystem::path& file) {
  const Site s{file, group_name + "/" + info.name};
  const auto rank = static_cast<int>(dims.size());
  Handle space =
      h5::space_handle(H5Screate_simple(rank, dims.data(), nullptr), s, "H5Screate_simple");
  const hid_t file_type = info.integer ? H5T_STD_I32LE : H5T_IEEE_F64LE;
  const hid_t mem_type = info.integer ? H5T_NATIVE_INT32 : H5T_NATIVE_DOUBLE;
  Handle dset = h5::dataset_handle(
      H5Dcreate2(group, info.name, file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
      s, "H5Dcreate2");
  if (!data.empty())
    h5::check_status(H5Dwrite(dset.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()),
                     "H5Dwrite", s.object, s.file);
  set_dataset_attributes(dset.get(), info, s);
}

/// Writes an N x columns (or N when columns == 0) dataset from row-major data.
template <class T>
void write_dataset(hid_t group, const std::string& group_name, const h5::DatasetInfo& info,
                   hsize_t n, const std::vector<T>& data, const std::filesystem::path& file) {
  if (info.columns > 0)
    write_array(group, group_name, info, {n, static_cast<hsize_t>(info.columns)}, data, file);
  else
    write_array(group, group_name, info, {n}, data, file);
}

/// Makes /xdmf/vertex_ids at least n long (0, 1, 2, ...).
void ensure_vertex_ids(hid_t file_id, hsize_t n, const std::filesystem::path& file) {
  const Site s{file, h5::kVertexIds};
  Handle dset = h5::dataset_handle(H5Dopen2(file_id, h5::kVertexIds, H5P_DEFAULT), s, "H5Dopen2");
  Handle space = h5::space_handle(H5Dget_space(dset.get()), s, "H5Dget_space");
  hsize_t current = 0;
  h5::check_status(H5Sget_simple_extent_dims(space.get(), &current, nullptr),
                   "H5Sget_simple_extent_dims", s.object, s.file);
  if (current >= n)
    return;
  h5::check_status(H5Dset_extent(dset.get(), &n), "H5Dset_extent", s.object, s.file);
  Handle fspace = h5::space_handle(H5Dget_space(dset.get()), s, "H5Dget_space");
  const hsize_t start = current, count = n - current;
  h5::check_status(
      H5Sselect_hyperslab(fspace.get(), H5S_SELECT_SET, &start, nullptr, &count, nullptr),
      "H5Sselect_hyperslab", s.object, s.file);
  Handle mspace = h5::space_handle(H5Screate_simple(1, &count, nullptr), s, "H5Screate_simple");
  std::vector<std::int64_t> ids(static_cast<std::size_t>(count));
  for (std::size_t i = 0; i < ids.size(); ++i)
    ids[i] = static_cast<std::int64_t>(current + i);
  h5::check_status(
      H5Dwrite(dset.get(), H5T_NATIVE_INT64, mspace.get(), fspace.get(), H5P_DEFAULT, ids.data()),
      "H5Dwrite", s.object, s.file);
}

/// Cauchy stress as a Tensor6 row (xx, xy, xz, yy, yz, zz), the order of every stress dataset.
void append_tensor6(std::vector<double>& buf, const Mat3& s) {
  const double t6[6] = {s(0, 0), s(0, 1), s(0, 2), s(1, 1), s(1, 2), s(2, 2)};
  buf.insert(buf.end(), t6, t6 + 6);
}

/// The physical nodes (ghost layers left out) of the box a recovery covers: their first
/// node's lattice coordinates and their count per direction (x, y, z; one node of z in 2D).
template <int Dim> struct GridBox {
  std::array<Index, 3> first{0, 0, 0}, nodes{1, 1, 1};
  explicit GridBox(const RecoveredStress<Dim>& r) {
    for (int d = 0; d < Dim; ++d) {
      const Index lo = std::max<Index>(r.first[d], 0);
      const Index hi = std::min<Index>(r.first[d] + r.count[d] - 1, r.grid.cells(d));
      first[static_cast<std::size_t>(d)] = lo;
      nodes[static_cast<std::size_t>(d)] = std::max<Index>(hi - lo + 1, 0);
    }
  }
  Vec3 origin(const Grid<Dim>& grid) const {
    Vec3 o = Vec3::Zero();
    for (int d = 0; d < Dim; ++d)
      o[d] = grid.origin()[d] +
             grid.cell_size() * static_cast<double>(first[static_cast<std::size_t>(d)]);
    return o;
  }
};

/// The grid/ group: node mass and stress on the physical nodes of the box the material's
/// stencils reach, shaped like the lattice (z, y, x: x fastest; one node of z in 2D), the shape
/// VTK's XDMF readers expect of a structured mesh's data, with the box's lattice as attributes.
template <int Dim>
void write_grid_group(hid_t frame, const std::string& frame_name, const RecoveredStress<Dim>& r,
                      const std::filesystem::path& file) {
  const std::string name = frame_name + "/" + h5::kGridGroup;
  const Site s{file, name};
  Handle g = h5::group_handle(
      H5Gcreate2(frame, h5::kGridGroup, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), s, "H5Gcreate2");
  const GridBox<Dim> box(r);
  const auto& nodes = box.nodes;
  const double h = r.grid.cell_size();
  const Vec3 origin = box.origin(r.grid);
  h5::write_double_attribute(g.get(), "origin", origin.data(), Dim, false, s);
  h5::write_double_attribute(g.get(), "spacing", &h, 1, true, s);
  h5::write_int64_attribute(g.get(), "nodes_x", nodes[0], s);
  h5::write_int64_attribute(g.get(), "nodes_y", nodes[1], s);
  if (Dim == 3)
    h5::write_int64_attribute(g.get(), "nodes_z", nodes[2], s);
  const auto count = static_cast<std::size_t>(nodes[0] * nodes[1] * nodes[2]);
  std::vector<double> mass, stress;
  mass.reserve(count);
  stress.reserve(6 * count);
  for (Index k = 0; k < nodes[2]; ++k)
    for (Index j = 0; j < nodes[1]; ++j)
      for (Index i = 0; i < nodes[0]; ++i) {
        std::array<Index, Dim> ijk{};
        ijk[0] = box.first[0] + i;
        ijk[1] = box.first[1] + j;
        if constexpr (Dim == 3)
          ijk[2] = box.first[2] + k;
        const std::size_t node = r.box_index(ijk);
        mass.push_back(r.node_mass[node]);
        stress.insert(stress.end(), r.node_stress[node].data(), r.node_stress[node].data() + 6);
      }
  const auto hx = static_cast<hsize_t>(nodes[0]), hy = static_cast<hsize_t>(nodes[1]),
             hz = static_cast<hsize_t>(nodes[2]);
  write_array(g.get(), name, h5::kGridMass, {hz, hy, hx}, mass, file);
  write_array(g.get(), name, h5::kGridStress, {hz, hy, hx, 6}, stress, file);
}

/// The voxels/ group: 4 (2D) or 8 (3D) corners per particle and the pattern colours.
template <int Dim>
void write_voxels_group(hid_t frame, const std::string& frame_name, const Voxels<Dim>& v,
                        const std::filesystem::path& file) {
  const std::string name = frame_name + "/" + h5::kVoxelsGroup;
  const Site s{file, name};
  Handle g = h5::group_handle(
      H5Gcreate2(frame, h5::kVoxelsGroup, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), s, "H5Gcreate2");
  constexpr int kCorners = Voxels<Dim>::kCorners;
  std::vector<double> corners;
  corners.reserve(static_cast<std::size_t>(kCorners * Dim) * v.corners.size());
  for (const auto& voxel : v.corners)
    for (const Vec<Dim>& c : voxel)
      corners.insert(corners.end(), c.data(), c.data() + Dim);
  const auto n = static_cast<hsize_t>(v.corners.size());
  write_dataset(g.get(), name, h5::in_dimension(h5::kVoxelCorners, Dim), kCorners * n, corners,
                file);
  write_dataset(g.get(), name, h5::kChecker, n, v.checker, file);
  write_dataset(g.get(), name, h5::kStripesHorizontal, n, v.stripes_horizontal, file);
  write_dataset(g.get(), name, h5::kStripesVertical, n, v.stripes_vertical, file);
}

void check_size(std::size_t size, Index n, const char* what) {
  if (static_cast<Index>(size) != n)
    throw std::invalid_argument("ResultsWriter::write_frame: particle array '" + std::string(what) +
                                "' has " + std::to_string(size) + " entries, expected " +
                                std::to_string(n));
}

/// Where a frame dataset's values come from: the particle array (its name and length) and how
/// its rows are appended to a buffer, or for an integer dataset the array itself.
struct FrameSource {
  const char* array = "";
  std::size_t length = 0;
  std::function<void(std::vector<double>&)> append;
  const Array<int>* integers = nullptr;
};

template <int Dim>
FrameSource frame_source(const std::string& name, const Particles<Dim>& p,
                         const FramePost<Dim>& post) {
  const auto vectors = [](const Array<Vec<Dim>>& a) {
    return [&a](std::vector<double>& buf) {
      for (const Vec<Dim>& v : a)
        buf.insert(buf.end(), v.data(), v.data() + Dim);
    };
  };
  const auto scalars = [](const std::vector<double>& a) {
    return [&a](std::vector<double>& buf) { buf.insert(buf.end(), a.begin(), a.end()); };
  };
  if (name == "position")
    return {"x", p.x.size(), vectors(p.x)};
  if (name == "velocity")
    return {"v", p.v.size(), vectors(p.v)};
  if (name == "reference_position")
    return {"x0", p.x0.size(), vectors(p.x0)};
  if (name == "mass")
    return {"mass", p.mass.size(), scalars(p.mass)};
  if (name == "volume")
    return {"volume", p.volume.size(), scalars(p.volume)};
  if (name == "pore_pressure")
    return {"pore pressure", p.pore_pressure.size(), scalars(p.pore_pressure)};
  if (name == "plastic_strain")
    return {"plastic strain", post.plastic_strain->size(), scalars(*post.plastic_strain)};
  if (name == "F")
    return {"F", p.F.size(), [&p](std::vector<double>& buf) {
              for (const Mat3& F : p.F)
                for (int r = 0; r < 3; ++r)
                  for (int c = 0; c < 3; ++c)
                    buf.push_back(F(r, c));
            }};
  if (name == "stress")
    return {"stress", p.stress.size(), [&p](std::vector<double>& buf) {
              for (const Mat3& s : p.stress)
                append_tensor6(buf, s);
            }};
  if (name == "effective_stress")
    return {"effective stress", p.stress.size(), [&p](std::vector<double>& buf) {
              for (std::size_t s = 0; s < p.stress.size(); ++s)
                append_tensor6(buf, p.stress[s] + p.pore_pressure[s] * Mat3::Identity());
            }};
  if (name == "material")
    return {"material", p.material.size(), {}, &p.material};
  if (name == "body")
    return {"body", p.body.size(), {}, &p.body};
  throw std::logic_error("ResultsWriter: no particle array for frame dataset " + name);
}

} // namespace

ResultsWriter::ResultsWriter(std::filesystem::path dir, RunMetadata metadata)
    : dir_(std::move(dir)), h5_path_(dir_ / "run.h5"), xmf_path_(dir_ / "run.xmf"),
      metadata_(std::move(metadata)) {
  h5::quiet();
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec)
    throw std::runtime_error("cannot create results directory '" + dir_.string() +
                             "': " + ec.message());
  // A sidecar left by an earlier run in this directory would point at frames that no longer
  // exist once run.h5 is replaced; the first write_frame creates the new one.
  std::filesystem::remove(xmf_path_, ec);
  std::filesystem::remove(xmf_path_.string() + ".tmp", ec);

  const auto& f = h5_path_;
  Handle file = h5::file_handle(H5Fcreate(f.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT),
                                Site{f, "/"}, "H5Fcreate");
  const Site root{f, "/"};
  h5::write_string_attribute(file.get(), "format", "talus-results", root);
  h5::write_int64_attribute(file.get(), "format_version", 1, root);

  {
    const Site s{f, "/metadata"};
    Handle g =
        h5::group_handle(H5Gcreate2(file.get(), "/metadata", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                         s, "H5Gcreate2");
    const auto& m = metadata_;
    h5::write_string_attribute(g.get(), "case_name", m.case_name, s);
    h5::write_string_attribute(g.get(), "case_file", m.case_file, s);
    h5::write_string_attribute(g.get(), "version", m.version, s);
    h5::write_int64_attribute(g.get(), "dimension", m.dimension, s);
    h5::write_string_attribute(g.get(), "geometry", m.geometry, s);
    const auto dims = static_cast<std::size_t>(m.dimension);
    h5::write_double_attribute(g.get(), "grid_origin", m.grid_origin.data(), dims, false, s);
    h5::write_double_attribute(g.get(), "grid_extent", m.grid_extent.data(), dims, false, s);
    h5::write_double_attribute(g.get(), "cell_size", &m.cell_size, 1, true, s);
    h5::write_string_attribute(g.get(), "material_names", join_lines(m.material_names), s);
    h5::write_string_attribute(g.get(), "body_names", join_lines(m.body_names), s);
    h5::write_string_attribute(g.get(), "overrides", join_lines(m.overrides), s);
    h5::write_string_attribute(g.get(), "length_unit", "m", s);
    h5::write_string_attribute(g.get(), "time_unit", "s", s);

    const Site c{f, "/metadata/case_text"};
    Handle type = h5::vl_string_type(c);
    Handle space = h5::space_handle(H5Screate(H5S_SCALAR), c, "H5Screate");
    Handle text = h5::dataset_handle(H5Dcreate2(g.get(), "case_text", type.get(), space.get(),
                                                H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                                     c, "H5Dcreate2");
    const char* p = m.case_text.c_str();
    h5::check_status(H5Dwrite(text.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, &p),
                     "H5Dwrite", c.object, c.file);
    h5::write_string_attribute(text.get(), "description", "the case file, verbatim", c);
  }
  {
    const Site s{f, "/frames"};
    Handle g = h5::group_handle(
        H5Gcreate2(file.get(), "/frames", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), s, "H5Gcreate2");
    h5::write_string_attribute(g.get(), "time_units", "s", s);
  }
  {
    const Site s{f, h5::kVertexIds};
    Handle g = h5::group_handle(
        H5Gcreate2(file.get(), "/xdmf", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), s, "H5Gcreate2");
    h5::write_string_attribute(g.get(), "description", "helper datasets referenced by run.xmf", s);
    const hsize_t zero = 0, unlimited = H5S_UNLIMITED, chunk = 4096;
    Handle space = h5::space_handle(H5Screate_simple(1, &zero, &unlimited), s, "H5Screate_simple");
    Handle dcpl = h5::plist_handle(H5Pcreate(H5P_DATASET_CREATE), s, "H5Pcreate");
    h5::check_status(H5Pset_chunk(dcpl.get(), 1, &chunk), "H5Pset_chunk", s.object, s.file);
    Handle d = h5::dataset_handle(H5Dcreate2(file.get(), h5::kVertexIds, H5T_STD_I64LE, space.get(),
                                             H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
                                  s, "H5Dcreate2");
    h5::write_string_attribute(d.get(), "description",
                               "0, 1, ..., N-1: Polyvertex connectivity for run.xmf", s);
  }
  h5::check_status(file.close(), "H5Fclose", "", f);
}

template <int Dim>
void ResultsWriter::write_frame(Index step, double time, const Particles<Dim>& p,
                                const std::vector<OutputField>& fields,
                                const FramePost<Dim>& post) {
  if (Dim != metadata_.dimension)
    throw std::invalid_argument("ResultsWriter::write_frame: particles of another dimension");
  h5::quiet();
  const Index n = p.size();
  const auto datasets = h5::frame_datasets(fields, Dim);
  if (std::find(fields.begin(), fields.end(), OutputField::PlasticStrain) != fields.end() &&
      !post.plastic_strain)
    throw std::invalid_argument(
        "ResultsWriter::write_frame: field plastic_strain requested without its values");
  // Every array checked before anything is written.
  std::vector<FrameSource> sources;
  for (const auto& d : datasets) {
    sources.push_back(frame_source(d.name, p, post));
    check_size(sources.back().length, n, sources.back().array);
  }
  if (post.stress)
    check_size(post.stress->smoothed_stress.size(), n, "smoothed stress");
  if (post.voxels)
    check_size(post.voxels->corners.size(), n, "voxel corners");

  const auto& f = h5_path_;
  const std::string gname = h5::frame_group_name(frames_);
  const Site gs{f, gname};
  Handle file = h5::open_for_append(f);
  // A group left by a frame whose write failed half-way is replaced.
  const htri_t exists = H5Lexists(file.get(), gname.c_str(), H5P_DEFAULT);
  h5::check_status(exists < 0 ? -1 : 0, "H5Lexists", gname, f);
  if (exists > 0)
    h5::check_status(H5Ldelete(file.get(), gname.c_str(), H5P_DEFAULT), "H5Ldelete", gname, f);
  {
    Handle gcpl = h5::plist_handle(H5Pcreate(H5P_GROUP_CREATE), gs, "H5Pcreate");
    h5::check_status(
        H5Pset_link_creation_order(gcpl.get(), H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED),
        "H5Pset_link_creation_order", gname, f);
    Handle g = h5::group_handle(
        H5Gcreate2(file.get(), gname.c_str(), H5P_DEFAULT, gcpl.get(), H5P_DEFAULT), gs,
        "H5Gcreate2");
    h5::write_double_attribute(g.get(), "time", &time, 1, true, gs);
    h5::write_int64_attribute(g.get(), "step", step, gs);

    const auto un = static_cast<std::size_t>(n);
    const auto hn = static_cast<hsize_t>(n);
    for (std::size_t k = 0; k < datasets.size(); ++k) {
      const auto& d = datasets[k];
      const FrameSource& src = sources[k];
      if (src.integers) {
        std::vector<std::int32_t> buf(src.integers->begin(), src.integers->end());
        write_dataset(g.get(), gname, d, hn, buf, f);
        continue;
      }
      std::vector<double> buf;
      buf.reserve(un * static_cast<std::size_t>(std::max(d.columns, 1)));
      src.append(buf);
      write_dataset(g.get(), gname, d, hn, buf, f);
    }
    if (post.stress) {
      std::vector<double> buf;
      buf.reserve(6 * un);
      for (const SymmetricStress& s : post.stress->smoothed_stress) // already Tensor6 order
        buf.insert(buf.end(), s.data(), s.data() + 6);
      write_dataset(g.get(), gname, h5::kStressSmoothed, hn, buf, f);
      write_grid_group<Dim>(g.get(), gname, *post.stress, f);
    }
    if (post.voxels)
      write_voxels_group<Dim>(g.get(), gname, *post.voxels, f);
  }
  // Voxels use 0 .. 4N-1 (8N-1 in 3D) as their quadrilateral (hexahedron) connectivity.
  ensure_vertex_ids(file.get(), static_cast<hsize_t>(post.voxels ? Voxels<Dim>::kCorners * n : n),
                    f);
  h5::check_status(file.close(), "H5Fclose", gname, f);

  FrameRecord info{step, time, n, fields, post.stress != nullptr, post.voxels != nullptr};
  if (post.stress) {
    const GridBox<Dim> box(*post.stress);
    info.grid_nodes = box.nodes;
    info.grid_origin = box.origin(post.stress->grid);
  }
  frame_info_.push_back(std::move(info));
  ++frames_;
  write_xdmf();
}

template void ResultsWriter::write_frame<2>(Index, double, const Particles<2>&,
                                            const std::vector<OutputField>&, const FramePost<2>&);
template void ResultsWriter::write_frame<3>(Index, double, const Particles<3>&,
                                            const std::vector<OutputField>&, const FramePost<3>&);

} // namespace talus
