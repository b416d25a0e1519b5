#include <iostream>

#include "terratraj/apps/cli.hpp"
#include "terratraj/apps/interrupt.hpp"

int main(int argc, char** argv) {
  const std::atomic<bool>& stop = terratraj::apps::installInterruptHandler();
  return terratraj::apps::runCli(argc, argv, std::cout, std::cerr, &stop);
}
