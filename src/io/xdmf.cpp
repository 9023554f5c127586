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

} // namespace

void ResultsWriter::write_xdmf() const {
  // run.h5 is referenced by its bare name: XDMF readers resolve it relative to run.xmf, so the
  // results folder can be moved or copied as a whole.
  const std::string h5 = h5_path_.filename().string();
  Index max_n = 0;
  for (const auto& fr : frame_info_)
    max_n = std::max(max_n, fr.particles);

  std::string x;
  x += "<?xml version=\"1.0\" ?>\n";
  x += "<!-- Talus particle frames; layout documented in docs/output-format.md -->\n";
  x += "<Xdmf Version=\"3.0\">\n";
  x += "  <Domain>\n";
  x += fmt::format("    <Grid Name=\"{}\" GridType=\"Collection\" CollectionType=\"Temporal\">\n",
                   xml_escape(metadata_.case_name.empty() ? "particles" : metadata_.case_name));
  for (std::size_t k = 0; k < frame_info_.size(); ++k) {
    const auto& fr = frame_info_[k];
    const std::string g = h5::frame_group_name(static_cast<long long>(k));
    const Index n = fr.particles;
    x += fmt::format("      <Grid Name=\"frame_{:06d}\" GridType=\"Uniform\">\n", k);
    x += fmt::format("        <Time Value=\"{:.17g}\"/>\n", fr.time);
    x += fmt::format("        <Information Name=\"step\" Value=\"{}\"/>\n", fr.step);
    // Explicit connectivity (a hyperslab 0..N-1 of /xdmf/vertex_ids): vtkXdmf3Reader builds
    // no cells for a Polyvertex topology without it, vtkXdmfReader builds N vertex cells
    // either way.
    x += fmt::format("        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{}\" "
                     "NodesPerElement=\"1\">\n",
                     n);
    x += fmt::format("          <DataItem ItemType=\"HyperSlab\" Dimensions=\"{}\" "
                     "Type=\"HyperSlab\">\n",
                     n);
    x += fmt::format("            <DataItem Dimensions=\"3 1\" Format=\"XML\">0 1 {}</DataItem>\n",
                     n);
    x += fmt::format("            <DataItem Dimensions=\"{}\" NumberType=\"Int\" Precision=\"8\" "
                     "Format=\"HDF\">{}:{}</DataItem>\n",
                     max_n, h5, h5::kVertexIds);
    x += "          </DataItem>\n";
    x += "        </Topology>\n";
    x += "        <Geometry GeometryType=\"XY\">\n";
    x += "          " + data_item(h5, g + "/position", n, 2, false) + "\n";
    x += "        </Geometry>\n";
    for (const auto& d : h5::frame_datasets(fr.fields)) {
      if (*d.xdmf_type == '\0')
        continue; // position is the geometry
      x += fmt::format("        <Attribute Name=\"{}\" AttributeType=\"{}\" Center=\"Node\">\n",
                       d.name, d.xdmf_type);
      x += "          " + data_item(h5, g + "/" + d.name, n, d.columns, d.integer) + "\n";
      x += "        </Attribute>\n";
    }
    x += "      </Grid>\n";
  }
  x += "    </Grid>\n";
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
