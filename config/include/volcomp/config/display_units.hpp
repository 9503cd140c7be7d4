#pragma once
/// Numbers as people read them on screen: lengths in micrometres and angles in microradians or
/// arcseconds, to 4 significant digits with at most 3 decimals (a nanometre or a nanoradian is
/// below anything a machine tool shows). Files, --json and CSV keep full precision in mm and rad;
/// these are for summaries and log lines only.

#include <string>
#include <string_view>

namespace volcomp::config {

/// `value` with 4 significant digits and at most 3 decimals, fixed notation, trailing zeros
/// dropped ("16.24", "1234", "0.012", "-3.25", "15.6", "250"); -0 prints as 0.
std::string significant(double value);

/// mm -> "16.24 um" (significant() of the value in um, with the unit).
std::string micrometres(double mm);

/// How angles are shown: microradians (the default) or arcseconds.
enum class AngleDisplay { Microradian, Arcsecond };

/// "urad" or "arcsec" -> AngleDisplay; throws std::invalid_argument on anything else.
AngleDisplay angleDisplayFromName(std::string_view name);

/// rad -> "12.5 urad" or "2.578 arcsec".
std::string angle(double rad, AngleDisplay display);

}  // namespace volcomp::config
