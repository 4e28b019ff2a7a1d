# FINken range-sensor simulation toolkit for Paparazzi UAV swarms.
#
#   make sim    run the example airframe (4 FINken in the arena), write logs, plots and a summary
#   make test   build everything, cross-compile the module logic (make cross) and run every test (C with cmocka/prove,
#               twice with sanitizers; Python with pytest)
#
# Both install what is missing first (Debian packages via apt-get, Python packages into build/venv).
# See README.md for the layout and the other targets.

SHELL := /bin/bash
.DEFAULT_GOAL := help
.DELETE_ON_ERROR:
.SUFFIXES:

BUILD    ?= build
OUT      ?= $(BUILD)/sim
AIRFRAME ?= conf/airframes/finken_nps.xml
VEHICLES ?= 4
SEED     ?= 1
DURATION ?= 180

# ---------------------------------------------------------------- set-up
DEBIAN_PACKAGES := gcc make perl pkg-config libcmocka-dev libgsl-dev libxml2-dev libxml2-utils \
                   libgpiod-dev python3 python3-venv
STAMPS := $(BUILD)/stamps
VENV   := $(BUILD)/venv
PY     := $(VENV)/bin/python

$(STAMPS)/debian: tools/ensure_debian_packages.sh
	@mkdir -p $(@D)
	@tools/ensure_debian_packages.sh $(DEBIAN_PACKAGES)
	@touch $@

# make paparazzi-check also builds the example airframe's autopilot for a Linux board (BeagleBone Black, armhf);
# make paparazzi-sim GCS=1 runs the GCS on Xvfb without a display; the check's ground step takes PprzGCS's picture
# (xdotool zooms its map, imagemagick's import grabs the screen)
PAPARAZZI_PACKAGES := gcc-arm-linux-gnueabihf g++-arm-linux-gnueabihf libgpiod-dev:armhf xvfb xauth xdotool imagemagick x11-utils
$(STAMPS)/debian-paparazzi: tools/ensure_debian_packages.sh | $(STAMPS)/debian
	@tools/ensure_debian_packages.sh $(PAPARAZZI_PACKAGES)
	@touch $@

# make test-valgrind (a step of make test) runs the C tests under valgrind
$(STAMPS)/debian-valgrind: tools/ensure_debian_packages.sh | $(STAMPS)/debian
	@tools/ensure_debian_packages.sh valgrind
	@touch $@

$(VENV)/.installed: tools/requirements.txt | $(STAMPS)/debian
	@echo "Creating the Python environment in $(VENV) (tools/requirements.txt)"
	@rm -rf $(VENV)
	@python3 -m venv $(VENV)
	@$(VENV)/bin/pip install --quiet --disable-pip-version-check -r tools/requirements.txt
	@touch $@

.PHONY: deps
deps: $(STAMPS)/debian $(VENV)/.installed

# ---------------------------------------------------------------- C build
CC       := gcc
WARN     := -std=gnu99 -Wall -Wextra -Werror
OPTIM    := -O2 -g
SANITIZE := -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
XML2_CFLAGS = $(shell pkg-config --cflags libxml-2.0)
LDLIBS   := -lgsl -lgslcblas -lxml2 -lm
GEN      := $(BUILD)/gen

# Sources by area (found, not listed: a new file in an area is built and tested without editing this file).
#   sw/simulator/nps         simulator-side models (pure C + GSL + libxml2) -> libfinken_nps (.a, and .so for Python)
#   sw/airborne/modules      module logic and glue, arch independent
#   sw/airborne/arch/sim     NPS variants;   sw/airborne/arch/linux   real Linux drivers
#   sim/pprz                 host stand-ins for the Paparazzi headers the modules include
find_c = $(shell find $(1) -name '*.c' 2>/dev/null | LC_ALL=C sort)
# Paparazzi flight-model glue (nps_fdm_<name>.c, e.g. nps_fdm_finken.c) includes Paparazzi's nps_fdm.h and generated
# headers: it is built only in a Paparazzi tree (module fdm_finken), not here; its pure core is.
NPS_SRCS    := $(filter-out sw/simulator/nps/nps_fdm_%.c,$(call find_c,sw/simulator/nps))
MODULE_SRCS := $(call find_c,sw/airborne/modules) $(call find_c,sim/pprz)
SIMARCH_SRCS   := $(call find_c,sw/airborne/arch/sim)
LINUXARCH_SRCS := $(call find_c,sw/airborne/arch/linux)
NPS_INC     := -Isw/simulator/nps
AIRBORNE_INC = -DPPRZ_HOST_MULTI_VEHICLE -Isw/airborne -Isim/pprz -I$(GEN) $(NPS_INC)
ABI_XML     := sim/pprz/abi_paparazzi.xml conf/abi_finken.xml

$(GEN)/abi_messages.h: tools/gen_abi.py $(ABI_XML) | $(VENV)/.installed
	@mkdir -p $(@D)
	$(PY) tools/gen_abi.py $(ABI_XML) -o $@

# $(1) = variant (plain | asan | fuzz), $(2) = extra compiler flags, $(3) = compiler (default $(CC)),
# $(4) = stamp of the Debian packages that compiler needs (default $(STAMPS)/debian)
define c_variant
$(1)_CFLAGS := $$(WARN) $$(OPTIM) -fPIC $(2)
$(1)_CC     := $(or $(3),$(CC))
$(1)_STAMP  := $(or $(4),$(STAMPS)/debian)
$(1)_NPS_OBJS   := $$(NPS_SRCS:%.c=$$(BUILD)/$(1)/nps/%.o)
$(1)_SIM_OBJS   := $$(patsubst %.c,$$(BUILD)/$(1)/sim/%.o,$$(MODULE_SRCS) $$(SIMARCH_SRCS))
$(1)_LINUX_OBJS := $$(patsubst %.c,$$(BUILD)/$(1)/linux/%.o,$$(MODULE_SRCS) $$(LINUXARCH_SRCS))

$$(BUILD)/$(1)/nps/%.o: %.c | $$($(1)_STAMP)
	@mkdir -p $$(@D)
	@echo "  CC [$(1)] $$<"
	@$$($(1)_CC) $$($(1)_CFLAGS) $$(NPS_INC) $$(XML2_CFLAGS) -MMD -MP -c $$< -o $$@
$$(BUILD)/$(1)/sim/%.o: %.c $$(GEN)/abi_messages.h | $$($(1)_STAMP)
	@mkdir -p $$(@D)
	@echo "  CC [$(1)/sim] $$<"
	@$$($(1)_CC) $$($(1)_CFLAGS) -Isw/airborne/arch/sim $$(AIRBORNE_INC) $$(XML2_CFLAGS) -MMD -MP -c $$< -o $$@
$$(BUILD)/$(1)/linux/%.o: %.c $$(GEN)/abi_messages.h | $$($(1)_STAMP)
	@mkdir -p $$(@D)
	@echo "  CC [$(1)/linux] $$<"
	@$$($(1)_CC) $$($(1)_CFLAGS) -Isw/airborne/arch/linux $$(AIRBORNE_INC) $$(XML2_CFLAGS) -MMD -MP -c $$< -o $$@

$$(BUILD)/$(1)/lib/libfinken_nps.a: $$($(1)_NPS_OBJS)
	@mkdir -p $$(@D)
	@rm -f $$@ && ar rcs $$@ $$^
$$(BUILD)/$(1)/lib/libairborne_sim.a: $$($(1)_SIM_OBJS)
	@mkdir -p $$(@D)
	@rm -f $$@ && ar rcs $$@ $$^
$$(BUILD)/$(1)/lib/libairborne_linux.a: $$($(1)_LINUX_OBJS)
	@mkdir -p $$(@D)
	@rm -f $$@ && ar rcs $$@ $$^

# C unit tests, one binary per file: tests/c/nps/test_*.c link the simulator models only,
# tests/c/airborne/test_*.c the modules built for NPS, tests/c/linux/test_*.c the modules with the Linux drivers.
$(1)_NPS_TESTS      := $$(patsubst tests/c/%.c,$$(BUILD)/$(1)/tests/%,$$(wildcard tests/c/nps/test_*.c))
$(1)_AIRBORNE_TESTS := $$(patsubst tests/c/%.c,$$(BUILD)/$(1)/tests/%,$$(wildcard tests/c/airborne/test_*.c))
$(1)_LINUX_TESTS    := $$(patsubst tests/c/%.c,$$(BUILD)/$(1)/tests/%,$$(wildcard tests/c/linux/test_*.c))
$$(BUILD)/$(1)/tests/nps/%: tests/c/nps/%.c $$(wildcard tests/c/*.h tests/c/nps/*.h) $$(BUILD)/$(1)/lib/libfinken_nps.a
	@mkdir -p $$(@D)
	@echo "  LD [$(1)] $$@"
	@$$($(1)_CC) $$($(1)_CFLAGS) -Itests/c $$(NPS_INC) $$(XML2_CFLAGS) $$< -o $$@ $$(BUILD)/$(1)/lib/libfinken_nps.a -lcmocka $$(LDLIBS)
$$(BUILD)/$(1)/tests/airborne/%: tests/c/airborne/%.c $$(wildcard tests/c/*.h tests/c/airborne/*.h) $$(BUILD)/$(1)/lib/libairborne_sim.a $$(BUILD)/$(1)/lib/libfinken_nps.a
	@mkdir -p $$(@D)
	@echo "  LD [$(1)] $$@"
	@$$($(1)_CC) $$($(1)_CFLAGS) -Itests/c -Isw/airborne/arch/sim $$(AIRBORNE_INC) $$(XML2_CFLAGS) $$< -o $$@ \
	  $$(BUILD)/$(1)/lib/libairborne_sim.a $$(BUILD)/$(1)/lib/libfinken_nps.a -lcmocka $$(LDLIBS)
$$(BUILD)/$(1)/tests/linux/%: tests/c/linux/%.c $$(wildcard tests/c/*.h tests/c/linux/*.h) $$(BUILD)/$(1)/lib/libairborne_linux.a $$(BUILD)/$(1)/lib/libfinken_nps.a
	@mkdir -p $$(@D)
	@echo "  LD [$(1)] $$@"
	@$$($(1)_CC) $$($(1)_CFLAGS) -Itests/c -Isw/airborne/arch/linux $$(AIRBORNE_INC) $$(XML2_CFLAGS) $$< -o $$@ \
	  $$(BUILD)/$(1)/lib/libairborne_linux.a $$(BUILD)/$(1)/lib/libfinken_nps.a -lcmocka -lgpiod $$(LDLIBS)
$(1)_TESTS := $$($(1)_NPS_TESTS) $$($(1)_AIRBORNE_TESTS) $$($(1)_LINUX_TESTS)
-include $$($(1)_NPS_OBJS:.o=.d) $$($(1)_SIM_OBJS:.o=.d) $$($(1)_LINUX_OBJS:.o=.d)
endef

$(eval $(call c_variant,plain,))
$(eval $(call c_variant,asan,$(SANITIZE)))

# The shared library the Python tools load through cffi (one implementation of every model).
LIBFINKEN_SO := $(BUILD)/lib/libfinken_nps.so
$(LIBFINKEN_SO): $(plain_NPS_OBJS)
	@mkdir -p $(@D)
	@echo "  LD $@"
	@$(CC) -shared -o $@ $^ $(LDLIBS)

# Pure module logic the Python tools call too (CAN ranging frame codec, candump parser): one implementation.
LIBFINKEN_CAN_SO := $(BUILD)/lib/libfinken_can.so
CAN_CODEC_SRCS   := sw/airborne/modules/ranging/ranging_can_frame.c sw/airborne/modules/ranging/ranging_can_candump.c
$(LIBFINKEN_CAN_SO): $(CAN_CODEC_SRCS) $(wildcard sw/airborne/modules/ranging/ranging_can_*.h) | $(STAMPS)/debian
	@mkdir -p $(@D)
	@echo "  LD $@"
	@$(CC) $(WARN) $(OPTIM) -fPIC -shared -Isw/airborne -o $@ $(CAN_CODEC_SRCS)

.PHONY: build
build: $(LIBFINKEN_SO) $(LIBFINKEN_CAN_SO) $(BUILD)/plain/lib/libairborne_sim.a $(BUILD)/plain/lib/libairborne_linux.a

# ---------------------------------------------------------------- tests
PYTEST_ENV := PYTHONPATH=tools FINKEN_LIB=$(abspath $(LIBFINKEN_SO)) FINKEN_CAN_LIB=$(abspath $(LIBFINKEN_CAN_SO)) FINKEN_BUILD=$(abspath $(BUILD)) MPLBACKEND=Agg
export CMOCKA_MESSAGE_OUTPUT := TAP
RUN_C_TESTS = ASAN_OPTIONS=detect_leaks=1:abort_on_error=0 UBSAN_OPTIONS=print_stacktrace=1 \
              prove --timer $(plain_TESTS) $(asan_TESTS)

# The plain C tests under valgrind's memcheck: uninitialised bytes used or written out, invalid accesses, leaks
# (tests/c/valgrind.supp says what it hides and why); two at a time.
VALGRIND := valgrind --error-exitcode=1 --leak-check=full --suppressions=tests/c/valgrind.supp -q
RUN_VALGRIND_TESTS = prove --timer -j2 --exec '$(VALGRIND)' $(plain_TESTS)
# Seconds of fuzzing per harness in make test (conf/Makefile.fuzz; make fuzz alone: FUZZ_SECONDS, 600)
FUZZ_TEST_SECONDS ?= 3

.PHONY: test test-c test-python test-valgrind
# cross: the module logic must build for an autopilot too (conf/Makefile.cross; prints its object sizes under a heading)
# The checks inside Paparazzi (pytest's and make paparazzi-check) run against PAPARAZZI_HOME, else against the tree
# the last make paparazzi-check was given (build/paparazzi/paparazzi_home) while it is still a prepared tree.
test: deps build cross $(plain_TESTS) $(asan_TESTS)
	@rc=0; \
	if pprz=$$($(PYTEST_ENV) $(PY) tools/paparazzi_check.py --find-tree --out $(BUILD)/paparazzi); then \
	  export PAPARAZZI_HOME="$$pprz"; echo "Paparazzi tree of the checks: $$pprz"; fi; \
	echo "== Python tests (pytest)"; \
	$(PYTEST_ENV) $(PY) -m pytest -q -p no:cacheprovider tests/python || rc=1; \
	echo "== C tests (cmocka, plain and with -fsanitize=address,undefined)"; \
	$(RUN_C_TESTS) || rc=1; \
	$(MAKE) --no-print-directory test-valgrind || rc=1; \
	$(MAKE) --no-print-directory fuzz FUZZ_SECONDS=$(FUZZ_TEST_SECONDS) FUZZ_KEEP_CORPUS=0 || rc=1; \
	echo "== Inside Paparazzi (make paparazzi-check)"; \
	if [ -n "$$PAPARAZZI_HOME" ]; then $(MAKE) --no-print-directory paparazzi-check || rc=1; \
	else echo "paparazzi-check: skipped ($$pprz; docs/paparazzi.md)"; fi; \
	exit $$rc

test-c: deps build $(plain_TESTS) $(asan_TESTS)
	@$(RUN_C_TESTS)

test-python: deps build
	@$(PYTEST_ENV) $(PY) -m pytest -q -p no:cacheprovider tests/python

test-valgrind: deps build $(plain_TESTS) | $(STAMPS)/debian-valgrind
	@echo "== C tests under valgrind (plain build, memcheck with leak check)"
	@$(RUN_VALGRIND_TESTS)

# ---------------------------------------------------------------- simulation
AIRFRAME_NAME := $(basename $(notdir $(AIRFRAME)))
HOST_DIR      := $(BUILD)/host/$(AIRFRAME_NAME)$(HOST_VARIANT)
HOST_BIN      := $(HOST_DIR)/nps_host
HOST_MODULES_MK := $(HOST_DIR)/modules.mk

# The generator reads the airframe and the module descriptors; sim/host.mk builds the host from what it wrote.
# HOST_DEFINES="NAME=VALUE ..." overrides airframe defines (HOST_VARIANT names the build, e.g. _detector_off).
$(HOST_MODULES_MK): $(AIRFRAME) $(wildcard conf/modules/*.xml) tools/gen_modules.py $(wildcard tools/finken/conf/*.py) | $(VENV)/.installed
	@$(PY) tools/gen_modules.py --airframe $(AIRFRAME) --modules conf/modules --out $(HOST_DIR) $(addprefix --define ,$(HOST_DEFINES))

.PHONY: host sim
host: $(HOST_MODULES_MK) $(GEN)/abi_messages.h | $(STAMPS)/debian
	@$(MAKE) --no-print-directory -f sim/host.mk HOST_DIR=$(HOST_DIR) GEN=$(GEN) CFLAGS_HOST="$(WARN) $(OPTIM)" XML2_CFLAGS="$(XML2_CFLAGS)" LDLIBS="$(LDLIBS)"

# The main job: the airframe with the wall detector feeding the swarm, and again with the swarm taking every
# echo (SWARM_USE_WALL_DETECTOR=FALSE), same seed; then the report (tables, metrics.json, plots) in OUT. Then the
# wall detector in a crowd: the detector-on host with the same options at 8 copters in SwarmLab and 16 in
# conf/arena/swarmlab_16.xml (OUT/crowd_8, OUT/crowd_16), a table and metrics.json's "crowd" (tools/sim_crowd.py).
# POSE_RATE=HZ: rows of poses.csv per copter and second (the host's --pose-rate; default the airframe's, 10 Hz).
SIM_ARGS = --vehicles $(VEHICLES) --seed $(SEED) --duration $(DURATION) $(if $(MODEL),--sensor-model $(MODEL)) $(if $(ARENA),--arena $(ARENA)) $(if $(INS_DRIFT),--ins-drift $(INS_DRIFT)) $(if $(POSE_RATE),--pose-rate $(POSE_RATE))
sim: deps build
	@$(MAKE) --no-print-directory host
	@$(MAKE) --no-print-directory host HOST_VARIANT=_detector_off HOST_DEFINES=SWARM_USE_WALL_DETECTOR=FALSE
	@echo "== Run 1/2: wall detector on -> $(OUT)"
	@$(HOST_BIN) $(SIM_ARGS) --out $(OUT)
	@echo "== Run 2/2: wall detector off -> $(OUT)/detector_off"
	@$(BUILD)/host/$(AIRFRAME_NAME)_detector_off/nps_host $(SIM_ARGS) --out $(OUT)/detector_off
	@$(PYTEST_ENV) $(PY) tools/sim_report.py --on $(OUT) --off $(OUT)/detector_off --airframe $(AIRFRAME) $(if $(ARENA),--arena $(ARENA))
	@$(PYTEST_ENV) $(PY) tools/sim_crowd.py --out $(OUT) --host $(HOST_BIN) --airframe $(AIRFRAME) -- $(SIM_ARGS)

# ---------------------------------------------------------------- inside Paparazzi
# Build and fly the example FINken aircraft in the Paparazzi tree PAPARAZZI_HOME (a scratch copy of it in
# build/paparazzi/tree: the tree itself is never modified). docs/paparazzi.md.
.PHONY: paparazzi-check
paparazzi-check: deps host $(STAMPS)/debian-paparazzi
	@$(PYTEST_ENV) $(PY) tools/paparazzi_check.py --out $(BUILD)/paparazzi

# A FINken swarm in Paparazzi's NPS: VEHICLES simsitl processes in one arena, DURATION simulated seconds with the wall
# detector and again without (SWARM_USE_WALL_DETECTOR=FALSE), merged logs and make sim's report in OUT (default
# build/paparazzi-sim; the scratch tree in build/paparazzi-sim/tree). TIME_FACTOR: simulated seconds per wall
# second; GCS=1 also starts Paparazzi's link, server and GCS; POSE_RATE=HZ: rows of poses.csv per aircraft and second
# (finken_world's FINKEN_WORLD_POSE_RATE); MODEL=file.xml: the sensor model every aircraft flies (FINKEN_WORLD_SENSOR_MODEL).
# docs/paparazzi.md: "A swarm in Paparazzi's NPS".
TIME_FACTOR ?= 1
PAPARAZZI_SIM_OUT = $(if $(filter file,$(origin OUT)),$(BUILD)/paparazzi-sim,$(OUT))
.PHONY: paparazzi-sim
paparazzi-sim: deps $(STAMPS)/debian-paparazzi
	@if [ -z "$$PAPARAZZI_HOME" ]; then echo "paparazzi-sim: PAPARAZZI_HOME is not set: make paparazzi-sim \
	PAPARAZZI_HOME=<a Paparazzi tree> (docs/paparazzi.md, From a clean tree)" >&2; exit 2; fi
	@$(PYTEST_ENV) $(PY) tools/paparazzi_sim.py --out $(PAPARAZZI_SIM_OUT) --tree $(BUILD)/paparazzi-sim/tree \
	  --vehicles $(VEHICLES) --duration $(DURATION) --time-factor $(TIME_FACTOR) --seed $(SEED) $(if $(filter-out 0,$(GCS)),--gcs) \
	  $(if $(POSE_RATE),--pose-rate $(POSE_RATE)) $(if $(MODEL),--sensor-model $(MODEL))

# Why several NPS processes on one Ivy bus crash: Paparazzi's nps_ivy.c calls ivy-c from two threads. Builds
# tests/paparazzi/ivy_two_threads.c against ivy-c (pkg-config ivy-c, as the tree's Makefile.nps) and runs 4 on one
# bus, with two threads and with one (docs/paparazzi.md, "One Ivy bus per aircraft").
.PHONY: paparazzi-ivy-race
paparazzi-ivy-race: deps
	@$(PYTEST_ENV) $(PY) tools/paparazzi_ivy_race.py

# ---------------------------------------------------------------- other targets
include conf/Makefile.cross
include conf/Makefile.calibrate
include conf/Makefile.imu
include conf/Makefile.bench
include conf/Makefile.fuzz
include conf/Makefile.sweep

# ---------------------------------------------------------------- misc
.PHONY: clean help
clean:
	rm -rf $(BUILD)

help:
	@echo "make sim    run $(AIRFRAME) with $(VEHICLES) copters (OUT=$(OUT), SEED=, DURATION=, AIRFRAME=, VEHICLES=, INS_DRIFT=SD[,TAU], POSE_RATE=Hz)"
	@echo "make test   run every test (and make cross)"
	@echo "make test-valgrind   the C tests under valgrind"
	@echo "make fuzz [FUZZ_SECONDS=600] [FUZZ_HARNESSES=fuzz_x]   run the libFuzzer harnesses (docs/fuzzing.md)"
	@echo "make calibrate MEASURED=log.csv MODEL=model.xml OUT=dir [SEED=] [FORCE=1]   discrepancy workflow"
	@echo "make evaluate MEASURED=log.csv MODEL=a.xml [MODEL2=b.xml ... MODEL9=] OUT=dir [SEED=] [FORCE=1]   score sensor models on a log without fitting"
	@echo "  (calibrate, evaluate: COLUMNS=measured=rng,... FILL=sensor=ranging,... UNIT=mm SPLIT_BY=recording read a lab's own CSV; calibrate: MAX_RANGE=15)"
	@echo "make imu-calibrate LOG=static_imu.csv OUT=dir [COLUMNS=] [GYRO_UNIT=deg/s] [ACCEL_UNIT=g] [TAU_MAX=s] [SIM_RATE=Hz]   IMU errors for the airframe (docs/imu-and-floor.md)"
	@echo "make validate   hidden-effect suite of the discrepancy workflow (build/validate/)"
	@echo "make rangelog READINGS=record.csv MOCAP=poses.csv ARENA=arena.xml OUT=log.csv [AIRFRAME=] [BODIES=] [CLOCK_OFFSET=]   a lab's flight to a range log (docs/calibration.md)"
	@echo "make sweep SWEEP=conf/sweeps/<name>.yaml [SCHEDULER=tcp://host:8786] [WORKERS=N] [OUT=]   Monte-Carlo sweep on Dask (docs/sweeps.md)"
	@echo "make bench  speed, scale and memory figures (build/bench.json)"
	@echo "make cross  compile the module logic for a Cortex-M4 autopilot (arm-none-eabi-gcc) and print sizes"
	@echo "make paparazzi-check PAPARAZZI_HOME=<tree>   build and fly the example aircraft in Paparazzi (scratch copy)"
	@echo "make paparazzi-sim PAPARAZZI_HOME=<tree> [VEHICLES=4 DURATION=180 TIME_FACTOR=1 SEED=1 GCS=1 POSE_RATE=Hz MODEL= OUT=]   a swarm in Paparazzi's NPS, detector on and off"
	@echo "make paparazzi-ivy-race   why several NPS processes on one Ivy bus crash (a reproducer; docs/paparazzi.md)"
	@echo "make clean  remove $(BUILD)/"
