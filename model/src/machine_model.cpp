#include "volcomp/model/machine_model.hpp"
