#include "volcomp/model/so3.hpp"
