/// libFuzzer target: the scenario parser (TOML, key tables, validation) on
/// arbitrary text. The only acceptable failure is conserve::InputError;
/// anything else (another exception, a crash, a sanitizer report) is a
/// finding. Mesh files resolve against a folder that does not exist.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/error.hpp"
#include "io/scenario.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const conserve::io::Scenario scenario = conserve::io::parse_scenario(text, "/nonexistent/fuzz.toml");
    (void)scenario;
  } catch (const conserve::InputError&) {
  }
  return 0;
}
