#include "gmc/apps/eval_app.h"

int main(int argc, char** argv) {
  return gmc::apps::runApp<gmc::apps::EvalApp>("gmc-eval", argc, argv);
}
