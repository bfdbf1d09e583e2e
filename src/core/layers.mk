# src/core/layers.mk: the core's domains and what each may include.
#   base   vectors, linear algebra, PRNG, speed profile, the real-time loop
#   arm    PUMA 560 model, kinematics, dynamics, joint and Cartesian control
#   carry  the two-arm carry: Petri net, event-referenced law, cell, rows
#   tdsd   task-decomposed singularity-damped motion planning
#   rover  the Pioneer team: unicycle, odometry, localizer, sonar, formation
# LAYER_<d> lists the domains src/core/<d> compiles against (the public
# headers include/tandem/<l>, and its own private ones): an include of any
# other domain's header finds a stub (build/layer/<d>/) that stops the build
# and names this rule; tools/lint.sh checks the same from the sources.
CORE_DOMAINS := base arm carry tdsd rover
LAYER_base   := base
LAYER_arm    := base arm
LAYER_carry  := base arm carry
LAYER_tdsd   := base arm tdsd
LAYER_rover  := base rover

# $(call core_domain,D): src/core/D's sources into the core library, compiled
# with its layer's include paths only (host and cross builds alike)
define core_domain
CORE_SRC  += $$(wildcard src/core/$(1)/*.c)
$$(OBJ)/src/core/$(1)/%.o: DIR_CPPFLAGS = $$(call core_cppflags,$(1))
$$(OBJ)/src/core/$(1)/%.o: CFLAGS += $$(CORE_OPT)
endef

# one stub per header a domain may not include (public or private)
LAYER_STAMP := $(LAYER)/.stamp
$(LAYER_STAMP): src/core/layers.mk $(wildcard include/tandem/*/*.h src/core/*/*.h)
	@rm -rf $(LAYER) && mkdir -p $(LAYER)
	@$(foreach d,$(CORE_DOMAINS),$(foreach o,$(filter-out $(LAYER_$(d)),$(CORE_DOMAINS)), \
	  for h in include/tandem/$(o)/*.h src/core/$(o)/*.h; do [ -e $$h ] || continue; mkdir -p $(LAYER)/$(d); \
	  printf '#error "layering: src/core/$(d) may include only include/tandem/{$(LAYER_$(d))} (src/core/layers.mk); %s is in %s"\n' $$(basename $$h) $$(dirname $$h) \
	    > $(LAYER)/$(d)/$$(basename $$h); done;))
	@touch $@

# make lint: the same table, checked from the sources (tools/lint.sh)
lint:
	@tools/lint.sh $(foreach d,$(CORE_DOMAINS),"$(d):$(LAYER_$(d))") -- $(CORE_FORBIDDEN)
	@tools/lint-docs.sh
	@tools/lint-state.sh $(OBJ)
