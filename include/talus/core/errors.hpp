#pragma once
// Error types that map onto the CLI's exit codes:
//   InputError     -> 2 (bad case file, bad option, non-physical value)
//   NumericalError -> 3 (blow-up, particle left the grid, Newton failure)
// Anything else that escapes is exit 1.
#include <stdexcept>
#include <string>

namespace talus {

/// Where in the user's input a problem sits: file:line:column plus the YAML key path.
struct SourceLocation {
  std::string file;     ///< case file path, or "--set" for command-line overrides
  int line = 0;         ///< 1-based; 0 when unknown
  int column = 0;       ///< 1-based; 0 when unknown
  std::string key_path; ///< e.g. "materials[0].youngs_modulus"
  std::string to_string() const;
};

class InputError : public std::runtime_error {
public:
  InputError(SourceLocation where, const std::string& what);
  const SourceLocation& where() const { return where_; }
  const std::string& detail() const { return detail_; }

private:
  SourceLocation where_;
  std::string detail_;
};

class NumericalError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

/// A material could not evaluate one of its points (det F <= 0, a return map that failed): the
/// message names the material, the point and the quantity; point() lets the caller add where
/// the point is.
class PointFailure : public NumericalError {
public:
  PointFailure(long long point, const std::string& what) : NumericalError(what), point_(point) {}
  long long point() const { return point_; }

private:
  long long point_;
};

/// Newton did not converge at the smallest load step an implicit analysis allows.
class NewtonStall : public NumericalError {
public:
  using NumericalError::NumericalError;
};

enum ExitCode : int { kExitOk = 0, kExitOther = 1, kExitBadInput = 2, kExitNumerical = 3 };

} // namespace talus
