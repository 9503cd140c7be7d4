#include "volcomp/config/config_error.hpp"
