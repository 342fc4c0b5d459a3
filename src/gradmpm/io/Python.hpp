#pragma once
// Runs a plotting script (embedded in the binary at build time) with the Python that
// has Debian's matplotlib: $GRADMPM_PYTHON if set, else /usr/bin/python3, else python3.
#include <string>
#include <string_view>
#include <vector>

namespace gradmpm {

std::string python_interpreter();

/// Runs `script` with `args`; throws std::runtime_error with Python's last error line on failure.
void run_python_script(std::string_view script, const std::vector<std::string>& args);

}  // namespace gradmpm
