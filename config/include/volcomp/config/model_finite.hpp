#pragma once
/// A model whose error is not finite somewhere in its travel is refused when it is read (start,
/// `volcomp check`, `volcompd --check-config` and every reload): a polynomial whose coefficients
/// overflow the double range over the travel, or grids and components that add up past it. A
/// file can hold no infinity itself (JSON has none), so this is the only way one arises, and the
/// daemon would otherwise run into a fault with the compensation removed.
///
/// Machine models are evaluated (E(q), mm, workpiece frame) along 201 points of each axis's
/// travel, with the other axes at the ends and the middle of theirs (an axis without a travel at
/// 0 mm), in both directions of motion; D-H chains at every joint value 0.

#include "volcomp/config/model_file.hpp"

namespace volcomp::config {

/// Throws ConfigError (the document's file; the key path of the first component whose value is
/// not finite, else "components", "grids" or "chain") naming the position.
void checkModelFinite(const ModelDocument& doc);

}  // namespace volcomp::config
