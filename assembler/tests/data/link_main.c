/* Linker test: cross-object references, a switch jump table, constructors, common
 * symbols, strings, scene header symbols. Built with -g -O2 for MIPS32r6 by the tests. */
struct component { unsigned addr, count; };
extern const struct component __trax_scene_triangles;
extern const struct component __trax_scene_bvh_nodes;

extern int util_scale(int x);
extern int util_table_sum(void);
extern int (*util_hooks[2])(int);
extern const char *util_name;
int shared_counter; /* common with -fcommon: also tentatively defined in link_util.c */
static int ctor_value;
static volatile int sink;

__attribute__((constructor)) static void main_init(void) { ctor_value = 40; }

__attribute__((noinline)) int classify(int x) {
  switch (x) {
  case 0: return util_scale(3);
  case 1: return 17;
  case 2: return ctor_value + 1;
  case 3: return shared_counter * 5;
  case 4: return (int)util_name[1];
  case 5: return 99;
  case 6: return util_table_sum();
  case 7: return -7;
  default: return x * 3;
  }
}

const char *const greetings[] = {"hello", "trax", "linker"};

int trax_main(void) {
  int acc = 0;
  for (int i = 0; i < 10; i++) acc += classify(i + sink);
  acc += util_hooks[0](acc) + util_hooks[1](2);
  acc += (int)__trax_scene_triangles.count + (int)__trax_scene_bvh_nodes.addr;
  acc += greetings[acc & 1][0];
  shared_counter += acc;
  return acc;
}
