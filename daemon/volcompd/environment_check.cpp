#include "environment_check.hpp"

#include <net/if.h>
#include <netdb.h>
#include <sys/socket.h>
#include <sys/stat.h>

#include <memory>

#include "volcomp/config/config_error.hpp"

namespace volcomp::volcompd {
namespace {

std::string resolveHost(const modbus::TcpLink& tcp, const std::string& file) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  const int rc = ::getaddrinfo(tcp.host.c_str(), std::to_string(tcp.port).c_str(), &hints, &found);
  if (rc != 0) {
    throw config::ConfigError(file, "transport.host",
                              "\"" + tcp.host + "\" does not resolve (" + ::gai_strerror(rc) +
                                  "): give the controller's IP address or a name this machine "
                                  "resolves (/etc/hosts)");
  }
  std::unique_ptr<addrinfo, decltype(&::freeaddrinfo)> guard(found, &::freeaddrinfo);
  char host[NI_MAXHOST] = "";
  ::getnameinfo(found->ai_addr, found->ai_addrlen, host, sizeof host, nullptr, 0, NI_NUMERICHOST);
  return "host " + tcp.host + " resolves to " + host;
}

std::string checkDevice(const modbus::RtuLink& rtu, const std::string& file) {
  struct stat st {};
  if (::stat(rtu.device.c_str(), &st) != 0) {
    throw config::ConfigError(file, "transport.device",
                              rtu.device +
                                  " does not exist: plug in the RS-485 adapter, or "
                                  "give its stable name (ls -l /dev/serial/by-id/)");
  }
  if (!S_ISCHR(st.st_mode)) {
    throw config::ConfigError(file, "transport.device",
                              rtu.device + " is not a character device (a serial port)");
  }
  return "device " + rtu.device + " exists";
}

std::string checkInterface(const can::CanLayout& layout, const std::string& file) {
  const std::string& name = layout.interfaceName;
  if (::if_nametoindex(name.c_str()) == 0) {
    const bool virtualCan = name.rfind("vcan", 0) == 0;
    throw config::ConfigError(
        file, "transport.interface",
        "the CAN interface " + name + " does not exist on this machine; " +
            (virtualCan ? "create it with: sudo modprobe vcan && sudo ip link add dev " + name +
                              " type vcan && sudo ip link set up " + name
                        : "check the adapter and its driver (ip -details link show), then bring "
                          "it up with: sudo ip link set " +
                              name + " up type can bitrate 500000 (the bus's bitrate)"));
  }
  return "CAN interface " + name + " exists";
}

}  // namespace

std::string checkTransportEnvironment(const config::TransportSettings& settings,
                                      const std::string& file) {
  if (const auto* modbus = std::get_if<modbus::ModbusSettings>(&settings)) {
    if (const auto* tcp = std::get_if<modbus::TcpLink>(&modbus->link)) {
      if (modbus->role == modbus::ModbusRole::Server) {
        return "the server listens on " + modbus->server.listenAddress + ":" +
               (tcp->port == 0 ? std::string("a free port") : std::to_string(tcp->port));
      }
      return resolveHost(*tcp, file);
    }
    return checkDevice(std::get<modbus::RtuLink>(modbus->link), file);
  }
  if (const auto* can = std::get_if<can::CanLayout>(&settings)) return checkInterface(*can, file);
  return "nothing to check on this machine for the " + config::transportType(settings) +
         " transport";
}

}  // namespace volcomp::volcompd
