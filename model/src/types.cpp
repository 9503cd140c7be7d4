#include "volcomp/model/types.hpp"
