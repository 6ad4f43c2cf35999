// Smallest flight-style program: links the installed static satgnc core, prints its version.
#include <cstdio>

#include "satgnc/version.hpp"

int main() {
  std::printf("satgnc %s\n", satgnc::version);
  return 0;
}
