#include "gmc/apps/map_export_app.h"

int main(int argc, char** argv) {
  return gmc::apps::runApp<gmc::apps::MapExportApp>("gmc-map-export", argc, argv);
}
