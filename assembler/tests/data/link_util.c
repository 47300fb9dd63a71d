/* Linker test, second object: data with pointers into the other object, weak symbols,
 * prioritised constructors, a common symbol and a large bss array. */
int shared_counter; /* common (built with -fcommon) */
int util_big_buffer[1000];
static int table[6] = {1, 1, 2, 3, 5, 8};
const char *util_name = "util";
extern int classify(int);
static int scale_factor = 2;

__attribute__((weak)) int util_weak_value(void) { return 5; }
__attribute__((constructor(101))) static void util_init_early(void) { scale_factor = 3; }
__attribute__((constructor)) static void util_init(void) { shared_counter = 1; }

int util_scale(int x) { return x * scale_factor + util_weak_value(); }

int util_table_sum(void) {
  int s = 0;
  for (int i = 0; i < 6; i++) s += table[i] + util_big_buffer[i * 100];
  return s;
}

static int twice(int x) { return classify(x) * 2; }
int (*util_hooks[2])(int) = {twice, util_scale};
