#include "volcomp/model/topology.hpp"
