#include <iostream>

#include "terratraj/apps/cli.hpp"

int main(int argc, char** argv) {
  return terratraj::apps::runCli(argc, argv, std::cout, std::cerr);
}
