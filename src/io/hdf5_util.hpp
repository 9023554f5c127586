#pragma once
// Private helpers shared by the results writer, reader and XDMF sidecar: RAII handles for HDF5
// ids, error checking that turns a failing HDF5 call into std::runtime_error naming the
// operation, the object and the file, opening a file for appending, string attributes, and the
// table of particle datasets (names, shapes, units) that defines the run.h5 frame layout
// (docs/output-format.md).
#include "talus/spec/case_spec.hpp"

#include <hdf5.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <thread>
#include <utility>
#include <vector>

namespace talus::h5 {

/// Switches off HDF5's automatic printing of its error stack; errors are reported through
/// exceptions instead. Cheap, so every public entry point calls it.
inline void quiet() {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

/// The innermost and outermost descriptions on the current HDF5 error stack, e.g.
/// "unable to open file (unable to lock file, errno = 11, ...)". Empty if the stack is empty.
inline std::string error_detail() {
  struct Walk {
    std::string first, last;
  } walk;
  auto cb = [](unsigned n, const H5E_error2_t* err, void* data) -> herr_t {
    auto* w = static_cast<Walk*>(data);
    const std::string desc = err->desc ? err->desc : "";
    if (n == 0)
      w->first = std::string(err->func_name ? err->func_name : "") + "(): " + desc;
    w->last = desc;
    return 0;
  };
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, cb, &walk);
  if (walk.first.empty())
    return {};
  if (walk.last.empty() || walk.first.ends_with(walk.last))
    return walk.first;
  return walk.first + " (" + walk.last + ")";
}

/// Throws std::runtime_error("HDF5: <op> failed for '<object>' in '<file>': <detail>").
[[noreturn]] inline void fail(std::string_view op, std::string_view object,
                              const std::filesystem::path& file) {
  std::string msg = "HDF5: " + std::string(op) + " failed";
  if (!object.empty())
    msg += " for '" + std::string(object) + "'";
  msg += " in '" + file.string() + "'";
  const std::string detail = error_detail();
  if (!detail.empty())
    msg += ": " + detail;
  H5Eclear2(H5E_DEFAULT);
  throw std::runtime_error(msg);
}

inline hid_t check(hid_t id, std::string_view op, std::string_view object,
                   const std::filesystem::path& file) {
  if (id < 0)
    fail(op, object, file);
  return id;
}

inline void check_status(herr_t status, std::string_view op, std::string_view object,
                         const std::filesystem::path& file) {
  if (status < 0)
    fail(op, object, file);
}

/// Owns one HDF5 id and closes it with the matching H5?close on destruction.
class Handle {
public:
  using Closer = herr_t (*)(hid_t);
  Handle() = default;
  Handle(hid_t id, Closer closer) : id_(id), closer_(closer) {}
  ~Handle() { reset(); }
  Handle(Handle&& o) noexcept : id_(std::exchange(o.id_, -1)), closer_(o.closer_) {}
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = std::exchange(o.id_, -1);
      closer_ = o.closer_;
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;

  hid_t get() const { return id_; }
  /// Closes now and reports a failing close (H5Fclose flushes, so its status matters).
  herr_t close() {
    herr_t status = 0;
    if (id_ >= 0 && closer_)
      status = closer_(id_);
    id_ = -1;
    return status;
  }
  void reset() { (void)close(); }
  /// Gives up ownership without closing.
  hid_t release() { return std::exchange(id_, -1); }

private:
  hid_t id_ = -1;
  Closer closer_ = nullptr;
};

// --- typed constructors of handles (all checked) -------------------------------------------------

struct Site {
  const std::filesystem::path& file;
  std::string object;
};

inline Handle file_handle(hid_t id, const Site& s, std::string_view op) {
  return {check(id, op, s.object, s.file), H5Fclose};
}
inline Handle group_handle(hid_t id, const Site& s, std::string_view op) {
  return {check(id, op, s.object, s.file), H5Gclose};
}
inline Handle dataset_handle(hid_t id, const Site& s, std::string_view op) {
  return {check(id, op, s.object, s.file), H5Dclose};
}
inline Handle attribute_handle(hid_t id, const Site& s, std::string_view op) {
  return {check(id, op, s.object, s.file), H5Aclose};
}
inline Handle space_handle(hid_t id, const Site& s, std::string_view op) {
  return {check(id, op, s.object, s.file), H5Sclose};
}
inline Handle type_handle(hid_t id, const Site& s, std::string_view op) {
  return {check(id, op, s.object, s.file), H5Tclose};
}
inline Handle plist_handle(hid_t id, const Site& s, std::string_view op) {
  return {check(id, op, s.object, s.file), H5Pclose};
}

/// Variable-length UTF-8 string type (how every text attribute and case_text are stored).
inline Handle vl_string_type(const Site& s) {
  Handle t = type_handle(H5Tcopy(H5T_C_S1), s, "H5Tcopy");
  check_status(H5Tset_size(t.get(), H5T_VARIABLE), "H5Tset_size", s.object, s.file);
  check_status(H5Tset_cset(t.get(), H5T_CSET_UTF8), "H5Tset_cset", s.object, s.file);
  return t;
}

// --- attributes ---------------------------------------------------------------------------------

inline void write_string_attribute(hid_t obj, const char* name, const std::string& value,
                                   const Site& s) {
  const Site a{s.file, s.object + "@" + name};
  Handle type = vl_string_type(a);
  Handle space = space_handle(H5Screate(H5S_SCALAR), a, "H5Screate");
  Handle attr = attribute_handle(
      H5Acreate2(obj, name, type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT), a, "H5Acreate2");
  const char* p = value.c_str();
  check_status(H5Awrite(attr.get(), type.get(), &p), "H5Awrite", a.object, a.file);
}

inline void write_double_attribute(hid_t obj, const char* name, const double* values, std::size_t n,
                                   bool scalar, const Site& s) {
  const Site a{s.file, s.object + "@" + name};
  const hsize_t dims[1] = {static_cast<hsize_t>(n)};
  Handle space = scalar ? space_handle(H5Screate(H5S_SCALAR), a, "H5Screate")
                        : space_handle(H5Screate_simple(1, dims, nullptr), a, "H5Screate_simple");
  Handle attr =
      attribute_handle(H5Acreate2(obj, name, H5T_IEEE_F64LE, space.get(), H5P_DEFAULT, H5P_DEFAULT),
                       a, "H5Acreate2");
  check_status(H5Awrite(attr.get(), H5T_NATIVE_DOUBLE, values), "H5Awrite", a.object, a.file);
}

inline void write_int64_attribute(hid_t obj, const char* name, std::int64_t value, const Site& s) {
  const Site a{s.file, s.object + "@" + name};
  Handle space = space_handle(H5Screate(H5S_SCALAR), a, "H5Screate");
  Handle attr = attribute_handle(
      H5Acreate2(obj, name, H5T_STD_I64LE, space.get(), H5P_DEFAULT, H5P_DEFAULT), a, "H5Acreate2");
  check_status(H5Awrite(attr.get(), H5T_NATIVE_INT64, &value), "H5Awrite", a.object, a.file);
}

/// Reads a string stored either as a variable-length or a fixed-length HDF5 string, from an
/// attribute (is_attribute) or a scalar dataset.
/// H5Fopen(RDWR), retried for a few seconds while another process holds a lock on the file
/// (HDF5 1.10 locks files it has open, e.g. a viewer reading the previous frame).
inline Handle open_for_append(const std::filesystem::path& file) {
  using namespace std::chrono_literals;
  const auto deadline = std::chrono::steady_clock::now() + 10s;
  for (;;) {
    const hid_t id = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    if (id >= 0)
      return {id, H5Fclose};
    // A lock held by another program clears; a file cut short by a kill does not.
    if (!std::filesystem::exists(file) || std::chrono::steady_clock::now() >= deadline ||
        error_detail().find("truncated file") != std::string::npos)
      fail("H5Fopen (read-write; is the file open in another program?)", "", file);
    std::this_thread::sleep_for(100ms);
  }
}

inline std::string read_string(hid_t id, bool is_attribute, const Site& s) {
  Handle ftype = type_handle(is_attribute ? H5Aget_type(id) : H5Dget_type(id), s,
                             is_attribute ? "H5Aget_type" : "H5Dget_type");
  if (H5Tget_class(ftype.get()) != H5T_STRING)
    throw std::runtime_error("HDF5: '" + s.object + "' in '" + s.file.string() +
                             "' is not a string");
  Handle space = space_handle(is_attribute ? H5Aget_space(id) : H5Dget_space(id), s,
                              is_attribute ? "H5Aget_space" : "H5Dget_space");
  if (H5Sget_simple_extent_npoints(space.get()) != 1)
    throw std::runtime_error("HDF5: '" + s.object + "' in '" + s.file.string() +
                             "' is not a single string");
  const htri_t vl = H5Tis_variable_str(ftype.get());
  check_status(vl < 0 ? -1 : 0, "H5Tis_variable_str", s.object, s.file);
  Handle mtype = type_handle(H5Tcopy(H5T_C_S1), s, "H5Tcopy");
  check_status(H5Tset_cset(mtype.get(), H5Tget_cset(ftype.get())), "H5Tset_cset", s.object, s.file);
  if (vl > 0) {
    check_status(H5Tset_size(mtype.get(), H5T_VARIABLE), "H5Tset_size", s.object, s.file);
    char* p = nullptr;
    const herr_t st = is_attribute ? H5Aread(id, mtype.get(), &p)
                                   : H5Dread(id, mtype.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, &p);
    check_status(st, is_attribute ? "H5Aread" : "H5Dread", s.object, s.file);
    std::string out = p ? p : "";
    H5free_memory(p);
    return out;
  }
  const std::size_t size = H5Tget_size(ftype.get());
  check_status(H5Tset_size(mtype.get(), size + 1), "H5Tset_size", s.object, s.file);
  check_status(H5Tset_strpad(mtype.get(), H5T_STR_NULLTERM), "H5Tset_strpad", s.object, s.file);
  std::vector<char> buf(size + 1, '\0');
  const herr_t st = is_attribute
                        ? H5Aread(id, mtype.get(), buf.data())
                        : H5Dread(id, mtype.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data());
  check_status(st, is_attribute ? "H5Aread" : "H5Dread", s.object, s.file);
  std::string out(buf.data());
  if (H5Tget_strpad(ftype.get()) == H5T_STR_SPACEPAD)
    out.erase(out.find_last_not_of(' ') + 1);
  return out;
}

// --- the frame layout ---------------------------------------------------------------------------

/// One particle dataset of a frame group.
struct DatasetInfo {
  const char* name;        ///< dataset name inside /frames/NNNNNN
  int columns;             ///< 0: 1-D dataset of N values; otherwise N x columns
  bool integer;            ///< int32 instead of float64
  const char* units;       ///< `units` attribute
  const char* description; ///< `description` attribute
  const char* xdmf_type;   ///< XDMF AttributeType ("" for the geometry)
};

// Vectors have as many columns as the run has dimensions (frame_datasets sets them; the
// constants hold the 2D count).
inline constexpr DatasetInfo kPosition{
    "position", 2, false, "m", "particle position (x, y; z in 3D)", ""};
inline constexpr DatasetInfo kVelocity{
    "velocity", 2, false, "m/s", "particle velocity (vx, vy; vz in 3D)", "Vector"};
inline constexpr DatasetInfo kMass{
    "mass", 0, false, "kg", "particle mass (2D: per unit thickness, a 1 m slice)", "Scalar"};
inline constexpr DatasetInfo kVolume{
    "volume", 0, false, "m^3", "current particle volume (2D: per unit thickness)", "Scalar"};
inline constexpr DatasetInfo kF{"F",
                                9,
                                false,
                                "1",
                                "deformation gradient, 3x3 row-major (F11 F12 F13 F21 ... F33); "
                                "plane strain: F13 = F23 = F31 = F32 = 0, F33 = 1",
                                "Tensor"};
inline constexpr DatasetInfo kStress{"stress",
                                     6,
                                     false,
                                     "Pa",
                                     "Cauchy stress, symmetric, XDMF Tensor6 order "
                                     "(xx, xy, xz, yy, yz, zz); tension positive",
                                     "Tensor6"};
inline constexpr DatasetInfo kMaterial{
    "material", 0, true, "1", "material index into /metadata@material_names", "Scalar"};
inline constexpr DatasetInfo kBody{"body",  0, true, "1", "body index into /metadata@body_names",
                                   "Scalar"};
inline constexpr DatasetInfo kPlasticStrain{
    "plastic_strain",
    0,
    false,
    "1",
    "accumulated equivalent plastic shear strain kappa = sum sqrt(2/3) |dev d eps^p| of the "
    "converged state; 0 for points of elastic materials",
    "Scalar"};
inline constexpr DatasetInfo kPorePressure{
    "pore_pressure",
    0,
    false,
    "Pa",
    "pore pressure u (compression positive) that the total stress holds: the effective stress "
    "is stress + u I",
    "Scalar"};
inline constexpr DatasetInfo kEffectiveStress{"effective_stress",
                                              6,
                                              false,
                                              "Pa",
                                              "effective stress stress + u I, symmetric, XDMF "
                                              "Tensor6 order (xx, xy, xz, yy, yz, zz); tension "
                                              "positive: what the material acts on",
                                              "Tensor6"};
inline constexpr DatasetInfo kReferencePosition{
    "reference_position",
    2,
    false,
    "m",
    "particle position in the reference configuration (its voxel's centre at t = 0; a split "
    "point's share of its parent's voxel): position - reference_position is the displacement",
    "Vector"};

// Post-processing datasets (output.stress_recovery, output.voxels).
inline constexpr DatasetInfo kStressSmoothed{
    "stress_smoothed",
    6,
    false,
    "Pa",
    "smoothed particle stress sigma_p^s = sum_i sigma_i Phi_ip (Andersen 2013), "
    "Tensor6 order like stress",
    "Tensor6"};
inline constexpr DatasetInfo kGridMass{
    "mass", 0, false, "kg", "node mass m_i = sum_p Phi_ip m_p per unit thickness", "Scalar"};
inline constexpr DatasetInfo kGridStress{
    "stress",
    6,
    false,
    "Pa",
    "grid-node stress sigma_i = sum_p sigma_p Phi_ip m_p / m_i (Andersen 2013), Tensor6 order; "
    "0 where mass = 0",
    "Tensor6"};
inline constexpr DatasetInfo kVoxelCorners{
    "corners",
    2,
    false,
    "m",
    "deformed voxel corners x_p + F_p (X_c - X_p): 2D rows 4p .. 4p+3 for particle p, "
    "counter-clockwise from the initial (-, -) corner; 3D rows 8p .. 8p+7, that square at z- "
    "then at z+ (VTK hexahedron order)",
    ""};
inline constexpr DatasetInfo kChecker{
    "checker", 0, true, "1", "checkerboard pattern (0/1) of the initial lattice", "Scalar"};
inline constexpr DatasetInfo kStripesHorizontal{"stripes_horizontal",
                                                0,
                                                true,
                                                "1",
                                                "horizontal stripes (0/1) of the initial lattice",
                                                "Scalar"};
inline constexpr DatasetInfo kStripesVertical{
    "stripes_vertical", 0, true, "1", "vertical stripes (0/1) of the initial lattice", "Scalar"};
inline constexpr const char* kGridGroup = "grid";
inline constexpr const char* kVoxelsGroup = "voxels";

/// A vector dataset with one column per dimension.
inline DatasetInfo in_dimension(DatasetInfo info, int dimension) {
  info.columns = dimension;
  return info;
}

/// Datasets of a frame in the order they are written, given the requested output fields
/// (duplicates ignored; position is always first).
inline std::vector<DatasetInfo> frame_datasets(const std::vector<OutputField>& fields,
                                               int dimension) {
  auto has = [&](OutputField f) {
    for (OutputField g : fields)
      if (g == f)
        return true;
    return false;
  };
  std::vector<DatasetInfo> out{in_dimension(kPosition, dimension)};
  if (has(OutputField::Velocity))
    out.push_back(in_dimension(kVelocity, dimension));
  if (has(OutputField::Mass))
    out.push_back(kMass);
  if (has(OutputField::Volume))
    out.push_back(kVolume);
  if (has(OutputField::DeformationGradient))
    out.push_back(kF);
  if (has(OutputField::Stress))
    out.push_back(kStress);
  if (has(OutputField::Material)) {
    out.push_back(kMaterial);
    out.push_back(kBody);
  }
  if (has(OutputField::PlasticStrain))
    out.push_back(kPlasticStrain);
  if (has(OutputField::ReferencePosition))
    out.push_back(in_dimension(kReferencePosition, dimension));
  if (has(OutputField::PorePressure))
    out.push_back(kPorePressure);
  if (has(OutputField::EffectiveStress))
    out.push_back(kEffectiveStress);
  return out;
}

/// "/frames/000003"
inline std::string frame_group_name(long long frame) {
  std::string digits = std::to_string(frame);
  if (digits.size() < 6)
    digits.insert(0, 6 - digits.size(), '0');
  return "/frames/" + digits;
}

/// Connectivity for the XDMF Polyvertex topology: 0, 1, ..., N_max - 1 (int64, extendible).
inline constexpr const char* kVertexIds = "/xdmf/vertex_ids";

} // namespace talus::h5
