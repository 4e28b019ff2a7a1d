# Builds the NPS-style host for one airframe (called by the top Makefile's `host` target).
# Inputs: HOST_DIR (holds the generator's modules.mk and generated/), GEN (abi_messages.h), CFLAGS_HOST,
# XML2_CFLAGS, LDLIBS.
#
# The host is one program optimised as a whole (link-time optimisation, HOST_LTO): the simulator's sources
# (sw/simulator/nps, built with their own include path and no airframe define) and the modules' are compiled
# here, so that the many small calls between them (geometry, grid, sensor chain, ABI callbacks) are inlined
# across files. The libraries of the tests and of Python stay plain -O2 objects.
.DELETE_ON_ERROR:
include $(HOST_DIR)/modules.mk

HOST_LTO ?= -flto=auto
# gcc turns sin(x) and cos(x) of the same x into one sincos call, and glibc's sincos saves and restores the
# MXCSR register: ~16 ns here against ~11 ns for the two calls, which give the same bits (checked on 5e7
# arguments). The sonar boresights and the emitters' cones need both, once per reading.
HOST_MATH := -fno-builtin-sin -fno-builtin-cos
# The ranging replay (--ranging-replay) decodes the bus with the Linux driver's pure logic.
HOST_REPLAY_SRCS := $(filter-out $(HOST_SRCS),$(addprefix sw/airborne/modules/ranging/,ranging_can_frame.c ranging_can_candump.c ranging_can_rx.c))
HOST_MAIN := $(wildcard sim/*.c) $(wildcard sim/pprz/*.c) $(HOST_REPLAY_SRCS)
HOST_OBJS := $(patsubst %.c,$(HOST_DIR)/obj/%.o,$(HOST_MAIN) $(HOST_SRCS))
HOST_NPS_OBJS := $(patsubst %.c,$(HOST_DIR)/obj/%.o,$(wildcard sw/simulator/nps/*.c))
HOST_CFLAGS := $(CFLAGS_HOST) $(HOST_LTO) $(HOST_MATH) -DPPRZ_HOST_MULTI_VEHICLE $(HOST_DEFS) -I$(HOST_DIR) -Isim \
               -Isw/airborne/arch/sim -Isw/airborne -Isim/pprz -I$(GEN) -Isw/simulator/nps $(XML2_CFLAGS) -pthread

$(HOST_DIR)/nps_host: $(HOST_OBJS) $(HOST_NPS_OBJS)
	@echo "  LD $@"
	@$(CC) $(CFLAGS_HOST) $(HOST_LTO) $(HOST_MATH) -pthread -o $@ $(HOST_OBJS) $(HOST_NPS_OBJS) $(LDLIBS)

# The simulator's sources: as in libfinken_nps (no airframe define), plus link-time optimisation.
$(HOST_NPS_OBJS): $(HOST_DIR)/obj/%.o: %.c sim/host.mk
	@mkdir -p $(@D)
	@echo "  CC [host] $<"
	@$(CC) $(CFLAGS_HOST) $(HOST_LTO) $(HOST_MATH) -Isw/simulator/nps $(XML2_CFLAGS) -MMD -MP -c $< -o $@

# Every object of the modules depends on the generated headers and definitions of this airframe (and every
# object on this file's flags).
$(HOST_DIR)/obj/%.o: %.c $(HOST_DIR)/modules.mk sim/host.mk
	@mkdir -p $(@D)
	@echo "  CC [host] $<"
	@$(CC) $(HOST_CFLAGS) -MMD -MP -c $< -o $@

-include $(HOST_OBJS:.o=.d) $(HOST_NPS_OBJS:.o=.d)
