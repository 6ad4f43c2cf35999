#include "satgnc/version.hpp"
