#include "gmc/apps/rgbd_mapping_app.h"

int main(int argc, char** argv) {
  return gmc::apps::runApp<gmc::apps::RgbdMappingApp>("gmc-rgbd-mapping", argc, argv);
}
