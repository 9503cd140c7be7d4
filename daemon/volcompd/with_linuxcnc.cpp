// volcompd-linuxcnc: every transport, LinuxCNC's HAL included.
#include <spdlog/spdlog.h>

#include <string_view>

#include "program.hpp"
#include "volcomp/linuxcnc/hal_port.hpp"

namespace volcomp::volcompd {

const char* const kProgramName = "volcompd-linuxcnc";

void requireTransportBuiltIn(const config::TransportSettings& /*settings*/,
                             const std::string& /*file*/) {}

std::unique_ptr<loop::ControllerPort> makeLinuxCncPort(const linuxcnc::HalSettings& settings,
                                                       const std::string& /*file*/) {
  // Joining LinuxCNC's HAL happens at connect (retried with the loop's backoff); what an operator
  // must know about it goes to the log, never from the cycle's read or write.
  return std::make_unique<linuxcnc::HalControllerPort>(settings, [](linuxcnc::NoticeLevel level,
                                                                    std::string_view line) {
    spdlog::log(level == linuxcnc::NoticeLevel::Warning ? spdlog::level::warn : spdlog::level::info,
                "linuxcnc: {}", line);
  });
}

}  // namespace volcomp::volcompd
