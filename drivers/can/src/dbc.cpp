#include "volcomp/can/dbc.hpp"

namespace volcomp::can {

std::vector<const DbcSignal*> DbcDatabase::find(std::string_view name) const {
  std::vector<const DbcSignal*> found;
  const std::size_t dot = name.find('.');
  const std::string_view messageName =
      dot == std::string_view::npos ? std::string_view{} : name.substr(0, dot);
  const std::string_view signalName = dot == std::string_view::npos ? name : name.substr(dot + 1);
  for (const DbcMessage& message : messages) {
    if (dot != std::string_view::npos && message.name != messageName) continue;
    for (const DbcSignal& signal : message.signals)
      if (signal.spec.name == signalName) found.push_back(&signal);
  }
  return found;
}

const DbcMessage* DbcDatabase::message(std::uint32_t id, bool extended) const noexcept {
  for (const DbcMessage& m : messages)
    if (m.id == id && m.extended == extended) return &m;
  return nullptr;
}

}  // namespace volcomp::can
