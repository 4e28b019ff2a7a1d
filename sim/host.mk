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
# not the Paparazzi flight-model glue nps_fdm_<name>.c (it includes Paparazzi's nps_fdm.h; see the Makefile's NPS_SRCS)
HOST_NPS_SRCS := $(filter-out sw/simulator/nps/nps_fdm_%.c,$(wildcard sw/simulator/nps/*.c))
HOST_INC := -DPPRZ_HOST_MULTI_VEHICLE $(HOST_DEFS) -I$(HOST_DIR) -Isim -Isw/airborne/arch/sim -Isw/airborne -Isim/pprz \
            -I$(GEN) -Isw/simulator/nps $(XML2_CFLAGS) -pthread

# Profile-guided optimisation (HOST_PGO=1, the default; HOST_PGO=0 builds once, without it). The host is first
# built instrumented (-fprofile-generate) in $(HOST_DIR)/train and run on the airframe's own arena and sensor model
# (TRAINING below: a few seconds); the host itself is then built with the branch and call counts it wrote
# (-fprofile-use), so gcc lays out the hot paths and inlines from measured frequencies: ~8 % faster at 4 copters
# (docs/host.md, "How the host is generated"). The floating-point operations are the same, so the logs are the same.
# -fprofile-partial-training keeps code the training did not run optimised as without a profile.
HOST_PGO ?= 1
.DEFAULT_GOAL := $(HOST_DIR)/nps_host
PGO_DIR := $(HOST_DIR)/train
PGO_PROFILE := $(abspath $(PGO_DIR)/profile)
# gcc names a source's counts (and tells its static functions apart) by the object's auxiliary name, which is
# derived from the object's path unless given: both builds give the same one (-dumpdir, -dumpbase per source)
PGO_NAMES = -dumpdir $(PGO_DIR)/names/$(dir $<) -dumpbase $(notdir $<)
PGO_GENERATE := -fprofile-generate=$(PGO_PROFILE) -fprofile-update=atomic
PGO_USE := -fprofile-use=$(PGO_PROFILE) -fprofile-partial-training
# 4 copters without and with logs (the benchmark's and make sim's runs), 16 copters (the copter grid's walks)
TRAINING := "--vehicles 4 --duration 1000 --no-logs" "--vehicles 4 --duration 60" "--vehicles 16 --duration 60 --no-logs"

# $(call host_objects,FOLDER,FLAGS,PROFILE,LABEL): rules for the host built into FOLDER/nps_host with the extra
# compiler FLAGS (none, or one of the PGO steps), each object also depending on PROFILE (the training's counts, or
# nothing); LABEL tags the build messages. The simulator's sources are built as in libfinken_nps (no airframe
# define); every module object depends on the generated headers and definitions of this airframe, and every
# object on this file.
define host_objects
HOST_OBJS_$(1) := $$(patsubst %.c,$(1)/obj/%.o,$$(HOST_MAIN) $$(HOST_SRCS))
HOST_NPS_OBJS_$(1) := $$(patsubst %.c,$(1)/obj/%.o,$$(HOST_NPS_SRCS))
$$(HOST_NPS_OBJS_$(1)): $(1)/obj/%.o: %.c sim/host.mk $(3)
	@mkdir -p $$(@D)
	@echo "  CC [host$(4)] $$<"
	@$$(CC) $$(CFLAGS_HOST) $$(HOST_LTO) $$(HOST_MATH) $(2) $(if $(2),$$(PGO_NAMES)) -Isw/simulator/nps $$(XML2_CFLAGS) -MMD -MP -MF $$(@:.o=.d) -c $$< -o $$@
$$(HOST_OBJS_$(1)): $(1)/obj/%.o: %.c $$(HOST_DIR)/modules.mk sim/host.mk $(3)
	@mkdir -p $$(@D)
	@echo "  CC [host$(4)] $$<"
	@$$(CC) $$(CFLAGS_HOST) $$(HOST_LTO) $$(HOST_MATH) $(2) $(if $(2),$$(PGO_NAMES)) $$(HOST_INC) -MMD -MP -MF $$(@:.o=.d) -c $$< -o $$@
$(1)/nps_host: $$(HOST_OBJS_$(1)) $$(HOST_NPS_OBJS_$(1))
	@echo "  LD $$@"
	@$$(CC) $$(CFLAGS_HOST) $$(HOST_LTO) $$(HOST_MATH) $(2) -pthread -o $$@ $$^ $$(LDLIBS)
-include $$(HOST_OBJS_$(1):.o=.d) $$(HOST_NPS_OBJS_$(1):.o=.d)
endef

ifeq ($(HOST_PGO),1)
$(eval $(call host_objects,$(PGO_DIR),$(PGO_GENERATE),, training))
$(eval $(call host_objects,$(HOST_DIR),$(PGO_USE),$(PGO_DIR)/profile.stamp))

# The training runs: a fresh profile each time (counts would add up over runs), one thread so that it is the same
# for every build.
$(PGO_DIR)/profile.stamp: $(PGO_DIR)/nps_host
	@echo "  PGO training runs of $<"
	@rm -rf $(PGO_PROFILE) $(PGO_DIR)/run
	@for args in $(TRAINING); do $< $$args --threads 1 --quiet --out $(PGO_DIR)/run || exit 1; done
	@rm -rf $(PGO_DIR)/run
	@touch $@
else
$(eval $(call host_objects,$(HOST_DIR),,))
endif
