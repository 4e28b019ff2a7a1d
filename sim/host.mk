# Builds the NPS-style host for one airframe (called by the top Makefile's `host` target).
# Inputs: HOST_DIR (holds the generator's modules.mk and generated/), GEN (abi_messages.h), NPS_LIB,
# CFLAGS_HOST, XML2_CFLAGS, LDLIBS.
.DELETE_ON_ERROR:
include $(HOST_DIR)/modules.mk

# The ranging replay (--ranging-replay) decodes the bus with the Linux driver's pure logic.
HOST_REPLAY_SRCS := $(filter-out $(HOST_SRCS),$(addprefix sw/airborne/modules/ranging/,ranging_can_frame.c ranging_can_candump.c ranging_can_rx.c))
HOST_MAIN := $(wildcard sim/*.c) $(wildcard sim/pprz/*.c) $(HOST_REPLAY_SRCS)
HOST_OBJS := $(patsubst %.c,$(HOST_DIR)/obj/%.o,$(HOST_MAIN) $(HOST_SRCS))
HOST_CFLAGS := $(CFLAGS_HOST) -DPPRZ_HOST_MULTI_VEHICLE $(HOST_DEFS) -I$(HOST_DIR) -Isim -Isw/airborne/arch/sim \
               -Isw/airborne -Isim/pprz -I$(GEN) -Isw/simulator/nps $(XML2_CFLAGS) -pthread

$(HOST_DIR)/nps_host: $(HOST_OBJS) $(NPS_LIB)
	@echo "  LD $@"
	@$(CC) -pthread -o $@ $(HOST_OBJS) $(NPS_LIB) $(LDLIBS)

# Every object depends on the generated headers and definitions of this airframe.
$(HOST_DIR)/obj/%.o: %.c $(HOST_DIR)/modules.mk
	@mkdir -p $(@D)
	@echo "  CC [host] $<"
	@$(CC) $(HOST_CFLAGS) -MMD -MP -c $< -o $@

-include $(HOST_OBJS:.o=.d)
