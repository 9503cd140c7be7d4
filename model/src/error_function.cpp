#include "volcomp/model/error_function.hpp"
