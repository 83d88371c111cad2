// What the core tells a user: errors (nothing was rendered) and warnings (something was skipped,
// with counts). The core writes every sentence; the faces (VTK filter and mapper, the Python
// binding) only pass them on, through vtkErrorMacro / vtkWarningMacro or VTK's events.
#pragma once

#include <sstream>
#include <string>
#include <vector>

namespace tetdsr
{

struct Messages
{
  std::vector<std::string> errors;
  std::vector<std::string> warnings;
  bool ok() const { return errors.empty(); }
};

/// The parts written one after another, as an ostream writes them.
template <typename... Parts>
std::string text(const Parts&... parts)
{
  std::ostringstream stream;
  (stream << ... << parts);
  return stream.str();
}

} // namespace tetdsr
