#pragma once
/// Fault-injection commands of the simulated machine, typed on stdin at run time (one per line)
/// or scheduled with `--event T:COMMAND[:ARG...]`:
///   stall [S]            receive requests but never answer (for S seconds; none/0 = until resume)
///   drop-link [S]        close the connection and refuse new ones (RTU: stay silent)
///   exception CODE [S]   answer every request with Modbus exception CODE (1..11)
///   garble-readback MM [S]  the X applied-offset read-back reports MM (what is applied is
///                        unchanged)
///   freeze [S]           the input registers keep their last values while the machine moves on
///   hold [S]             feed hold: the machine stops on its path
///   late-reply S [N]     apply the next N writes (default 1) but answer each S seconds late
///   no-reply [N]         apply the next N writes (default 1) but never answer them
///   pause-client PID S   before answering the next read, stop process PID (SIGSTOP) and continue
///                        it (SIGCONT) S seconds later: stopped between its read and its write
///   enable on|off        the compensation enable input
///   homed on|off         the homed input
///   ack on|off           the fault-acknowledge input
///   resume               end stall, drop-link, exception, freeze and hold
///   status               print "STATUS " and the report so far (one line) on stdout
///   quit                 end the run now (report and exit)

#include <optional>
#include <string>
#include <string_view>

#include "volcomp/sim/machine.hpp"

namespace volcomp::sim {

struct Command {
  enum class Kind {
    Stall,
    DropLink,
    Exception,
    Freeze,
    Hold,
    LateReply,
    NoReply,
    PauseClient,
    GarbleReadback,
    Enable,
    Homed,
    Ack,
    Resume,
    Status,
    Quit
  };
  Kind kind = Kind::Resume;
  double durationS = 0.0;
  int exceptionCode = 0;
  int count = 1;         ///< late-reply, no-reply: number of writes
  int pid = 0;           ///< pause-client
  double valueMm = 0.0;  ///< garble-readback
  bool on = true;
};

/// Parses one command line (words separated by spaces, tabs or ':'). Throws std::invalid_argument
/// with a message saying what was expected.
Command parseCommand(std::string_view text);

struct ScheduledEvent {
  double atS = 0.0;  ///< seconds after the start
  Command command;
};

/// Parses "T:COMMAND[:ARG...]", e.g. "2.5:drop-link:1" or "4:enable:off".
ScheduledEvent parseEvent(std::string_view spec);

/// Applies a command to the machine at time t. Returns false for quit; status is the caller's.
bool applyCommand(Machine& machine, double tS, const Command& command);

}  // namespace volcomp::sim
