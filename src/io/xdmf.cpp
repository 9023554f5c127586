// run.xmf: the XDMF sidecar that lets ParaView/VisIt open run.h5 as a time series of particle
// clouds. Rewritten after every frame through run.xmf.tmp + rename, so a reader never sees a
// half-written file. Choices and the reasons for them: docs/output-format.md.
#include "talus/io/results.hpp"

#include "hdf5_util.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <system_error>

namespace talus {

namespace {

std::string data_item(const std::string& h5_name, const std::string& path, Index rows, int cols,
                      bool integer) {
  const std::string dims = cols > 0 ? fmt::format("{} {}", rows, cols) : fmt::format("{}", rows);
  return fmt::format(
      R"(<DataItem Dimensions="{}" NumberType="{}" Precision="{}" Format="HDF">{}:{}</DataItem>)",
      dims, integer ? "Int" : "Float", integer ? 4 : 8, h5_name, path);
}

std::string xml_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
    case '&':
      out += "&amp;";
      break;
    case '<':
      out += "&lt;";
      break;
    case '>':
      out += "&gt;";
      break;
    case '"':
      out += "&quot;";
      break;
    default:
      out += c;
    }
  }
  return out;
}

std::string attribute(const std::string& name, const char* type, const char* center,
                      const std::string& item) {
  return fmt::format("        <Attribute Name=\"{}\" AttributeType=\"{}\" Center=\"{}\">\n"
                     "          {}\n"
                     "        </Attribute>\n",
                     name, type, center, item);
}

/// Opening of one time step's grid: name, time and solver step.
std::string frame_header(std::size_t k, double time, Index step) {
  return fmt::format("      <Grid Name=\"frame_{:06d}\" GridType=\"Uniform\">\n"
                     "        <Time Value=\"{:.17g}\"/>\n"
                     "        <Information Name=\"step\" Value=\"{}\"/>\n",
                     k, time, step);
}

/// Connectivity 0, 1, ..., count - 1 as a hyperslab of /xdmf/vertex_ids (length ids_length).
std::string vertex_ids(const std::string& dims, Index count, Index ids_length,
                       const std::string& h5) {
  return fmt::format("          <DataItem ItemType=\"HyperSlab\" Dimensions=\"{}\" "
                     "Type=\"HyperSlab\">\n"
                     "            <DataItem Dimensions=\"3 1\" Format=\"XML\">0 1 {}</DataItem>\n"
                     "            <DataItem Dimensions=\"{}\" NumberType=\"Int\" Precision=\"8\" "
                     "Format=\"HDF\">{}:{}</DataItem>\n"
                     "          </DataItem>\n",
                     dims, count, ids_length, h5, h5::kVertexIds);
}

} // namespace

void ResultsWriter::write_xdmf() const {
  // run.h5 is referenced by its bare name: XDMF readers resolve it relative to run.xmf, so the
  // results folder can be moved or copied as a whole.
  const std::string h5 = h5_path_.filename().string();
  const int dims = metadata_.dimension;
  const char* geometry = dims == 3 ? "XYZ" : "XY";
  const Index corners = Index{1} << dims; // per voxel
  Index ids_length = 0;                   // the length of /xdmf/vertex_ids
  bool any_voxels = false, any_grid = false;
  for (const auto& fr : frame_info_) {
    ids_length = std::max(ids_length, fr.voxels ? corners * fr.particles : fr.particles);
    any_voxels = any_voxels || fr.voxels;
    any_grid = any_grid || fr.recovered;
  }
  const std::string case_name =
      xml_escape(metadata_.case_name.empty() ? "particles" : metadata_.case_name);

  std::string x;
  x += "<?xml version=\"1.0\" ?>\n";
  x += "<!-- Talus frames: particles, then deformed voxels and grid fields when the case writes "
       "them; layout documented in docs/output-format.md -->\n";
  x += "<Xdmf Version=\"3.0\">\n";
  x += "  <Domain>\n";
  x += fmt::format("    <Grid Name=\"{}\" GridType=\"Collection\" CollectionType=\"Temporal\">\n",
                   case_name);
  for (std::size_t k = 0; k < frame_info_.size(); ++k) {
    const auto& fr = frame_info_[k];
    const std::string g = h5::frame_group_name(static_cast<long long>(k));
    const Index n = fr.particles;
    x += frame_header(k, fr.time, fr.step);
    // Explicit connectivity (a hyperslab 0..N-1 of /xdmf/vertex_ids): vtkXdmf3Reader builds
    // no cells for a Polyvertex topology without it, vtkXdmfReader builds N vertex cells
    // either way.
    x += fmt::format("        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{}\" "
                     "NodesPerElement=\"1\">\n",
                     n);
    x += vertex_ids(std::to_string(n), n, ids_length, h5);
    x += "        </Topology>\n";
    x += fmt::format("        <Geometry GeometryType=\"{}\">\n", geometry);
    x += "          " + data_item(h5, g + "/position", n, dims, false) + "\n";
    x += "        </Geometry>\n";
    for (const auto& d : h5::frame_datasets(fr.fields, dims)) {
      if (*d.xdmf_type == '\0')
        continue; // position is the geometry
      x += attribute(d.name, d.xdmf_type, "Node",
                     data_item(h5, g + "/" + d.name, n, d.columns, d.integer));
    }
    if (fr.recovered)
      x += attribute(h5::kStressSmoothed.name, "Tensor6", "Node",
                     data_item(h5, g + "/" + h5::kStressSmoothed.name, n, 6, false));
    x += "      </Grid>\n";
  }
  x += "    </Grid>\n";

  if (any_voxels) {
    // Each voxel is a quadrilateral (hexahedron) cell; the particle datasets are its cell data.
    x += fmt::format("    <Grid Name=\"{}_voxels\" GridType=\"Collection\" "
                     "CollectionType=\"Temporal\">\n",
                     case_name);
    for (std::size_t k = 0; k < frame_info_.size(); ++k) {
      const auto& fr = frame_info_[k];
      if (!fr.voxels)
        continue;
      const std::string g = h5::frame_group_name(static_cast<long long>(k));
      const std::string v = g + "/" + h5::kVoxelsGroup;
      const Index n = fr.particles;
      x += frame_header(k, fr.time, fr.step);
      x += fmt::format("        <Topology TopologyType=\"{}\" NumberOfElements=\"{}\">\n",
                       dims == 3 ? "Hexahedron" : "Quadrilateral", n);
      x += vertex_ids(fmt::format("{} {}", n, corners), corners * n, ids_length, h5);
      x += "        </Topology>\n";
      x += fmt::format("        <Geometry GeometryType=\"{}\">\n", geometry);
      x += "          " + data_item(h5, v + "/corners", corners * n, dims, false) + "\n";
      x += "        </Geometry>\n";
      for (const auto& d : h5::frame_datasets(fr.fields, dims)) {
        if (*d.xdmf_type == '\0')
          continue;
        x += attribute(d.name, d.xdmf_type, "Cell",
                       data_item(h5, g + "/" + d.name, n, d.columns, d.integer));
      }
      if (fr.recovered)
        x += attribute(h5::kStressSmoothed.name, "Tensor6", "Cell",
                       data_item(h5, g + "/" + h5::kStressSmoothed.name, n, 6, false));
      for (const auto& d : {h5::kChecker, h5::kStripesHorizontal, h5::kStripesVertical})
        x += attribute(d.name, d.xdmf_type, "Cell", data_item(h5, v + "/" + d.name, n, 0, true));
      x += "      </Grid>\n";
    }
    x += "    </Grid>\n";
  }

  if (any_grid) {
    // The physical grid nodes as a structured mesh. In 2D a 3DCoRectMesh one node thick: both
    // VTK XDMF readers map a 2DCoRectMesh onto the wrong axes. XDMF lists dimensions, origin
    // and spacing slowest first (z, y, x). Each frame's mesh is the box its material reaches.
    const double h = metadata_.cell_size;
    x += fmt::format("    <Grid Name=\"{}_grid\" GridType=\"Collection\" "
                     "CollectionType=\"Temporal\">\n",
                     case_name);
    for (std::size_t k = 0; k < frame_info_.size(); ++k) {
      const auto& fr = frame_info_[k];
      if (!fr.recovered)
        continue;
      const std::string gg = h5::frame_group_name(static_cast<long long>(k)) + "/" + h5::kGridGroup;
      const Index nx = fr.grid_nodes[0], ny = fr.grid_nodes[1], nz = fr.grid_nodes[2];
      const double oz = dims == 3 ? fr.grid_origin.z() : 0.0;
      x += frame_header(k, fr.time, fr.step);
      x +=
          fmt::format("        <Topology TopologyType=\"3DCoRectMesh\" Dimensions=\"{} {} {}\"/>\n",
                      nz, ny, nx);
      x += "        <Geometry GeometryType=\"ORIGIN_DXDYDZ\">\n";
      x += fmt::format("          <DataItem Dimensions=\"3\" NumberType=\"Float\" Precision=\"8\" "
                       "Format=\"XML\">{:.17g} {:.17g} {:.17g}</DataItem>\n",
                       oz, fr.grid_origin.y(), fr.grid_origin.x());
      x += fmt::format("          <DataItem Dimensions=\"3\" NumberType=\"Float\" Precision=\"8\" "
                       "Format=\"XML\">{:.17g} {:.17g} {:.17g}</DataItem>\n",
                       h, h, h);
      x += "        </Geometry>\n";
      for (const auto& d : {h5::kGridMass, h5::kGridStress})
        x += attribute(d.name, d.xdmf_type, "Node",
                       fmt::format("<DataItem Dimensions=\"{} {} {}{}\" NumberType=\"Float\" "
                                   "Precision=\"8\" Format=\"HDF\">{}:{}/{}</DataItem>",
                                   nz, ny, nx, d.columns ? fmt::format(" {}", d.columns) : "", h5,
                                   gg, d.name));
      x += "      </Grid>\n";
    }
    x += "    </Grid>\n";
  }
  x += "  </Domain>\n";
  x += "</Xdmf>\n";

  const std::filesystem::path tmp = xmf_path_.string() + ".tmp";
  std::FILE* out = std::fopen(tmp.c_str(), "wb");
  if (!out)
    throw std::runtime_error("cannot write '" + tmp.string() + "': " + std::strerror(errno));
  const bool written = std::fwrite(x.data(), 1, x.size(), out) == x.size();
  const bool flushed = std::fflush(out) == 0;
  const bool closed = std::fclose(out) == 0;
  if (!written || !flushed || !closed)
    throw std::runtime_error("cannot write '" + tmp.string() + "': " + std::strerror(errno));
  std::error_code ec;
  std::filesystem::rename(tmp, xmf_path_, ec);
  if (ec)
    throw std::runtime_error("cannot rename '" + tmp.string() + "' to '" + xmf_path_.string() +
                             "': " + ec.message());
}

} // namespace talus
