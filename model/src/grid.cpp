#include "volcomp/model/grid.hpp"
