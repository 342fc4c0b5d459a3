#include "gradmpm/io/Python.hpp"

#include <fmt/format.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "gradmpm/core/Errors.hpp"

namespace gradmpm {

namespace fs = std::filesystem;

std::string python_interpreter() {
  if (const char* env = std::getenv("GRADMPM_PYTHON"); env && *env) return env;
  if (fs::exists("/usr/bin/python3")) return "/usr/bin/python3";
  return "python3";
}

namespace {
std::string shell_quote(const std::string& s) {
  std::string q(1, '\'');
  for (char c : s) {
    if (c == '\'')
      q.append("'\\''");
    else
      q.push_back(c);
  }
  q.push_back('\'');
  return q;
}
}  // namespace

void run_python_script(std::string_view script, const std::vector<std::string>& args) {
  const fs::path dir = fs::temp_directory_path();
  const fs::path script_path = dir / fmt::format("gradmpm-plot-{}.py", ::getpid());
  const fs::path log_path = dir / fmt::format("gradmpm-plot-{}.log", ::getpid());
  {
    std::ofstream out(script_path);
    out << script;
    if (!out) throw OutputError(fmt::format("{}: cannot write the plotting script", script_path.string()));
  }
  std::string cmd = shell_quote(python_interpreter()) + " " + shell_quote(script_path.string());
  for (const auto& a : args) cmd.append(" ").append(shell_quote(a));
  cmd.append(" >").append(shell_quote(log_path.string())).append(" 2>&1");
  const int status = std::system(cmd.c_str());

  std::ifstream log(log_path);
  std::stringstream text;
  text << log.rdbuf();
  std::error_code ec;
  fs::remove(script_path, ec);
  fs::remove(log_path, ec);
  if (status != 0) {
    std::string msg = text.str();
    while (!msg.empty() && (msg.back() == '\n' || msg.back() == ' ')) msg.pop_back();
    const std::size_t last = msg.rfind('\n');
    if (last != std::string::npos) msg = msg.substr(last + 1);
    throw std::runtime_error(fmt::format("plotting with {} failed (exit status {}): {}", python_interpreter(),
                                         WIFEXITED(status) ? WEXITSTATUS(status) : status, msg));
  }
}

}  // namespace gradmpm
