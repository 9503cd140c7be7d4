#include "volcomp/model/dh_chain.hpp"
