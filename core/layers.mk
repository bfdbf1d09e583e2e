# core/layers.mk: the core's domains and what each may include.
#   base   vectors, linear algebra, PRNG, speed profile, the real-time loop
#   arm    PUMA 560 model, kinematics, dynamics, joint and Cartesian control
#   carry  the two-arm carry: Petri net, event-referenced law, cell, rows
#   tdsd   task-decomposed singularity-damped motion planning
#   rover  the Pioneer team: unicycle, odometry, localizer, sonar, formation
# LAYER_<d> lists the folders core/<d> compiles against: an include of any
# other domain's header finds a stub (build/layer/<d>/) that stops the build
# and names this rule; tools/lint.sh checks the same from the sources.
CORE_DOMAINS := base arm carry tdsd rover
LAYER_base   := base
LAYER_arm    := base arm
LAYER_carry  := base arm carry
LAYER_tdsd   := base arm tdsd
LAYER_rover  := base rover

# $(call core_domain,D): core/D's sources into the core library, compiled
# with its layer's include paths only (host and cross builds alike)
define core_domain
CORE_DIRS += core/$(1)
CORE_SRC  += $$(wildcard core/$(1)/*.c)
$$(OBJ)/core/$(1)/%.o: DIR_CPPFLAGS = $$(call core_cppflags,$(1))
endef

# one stub per header a domain may not include
LAYER_STAMP := $(LAYER)/.stamp
$(LAYER_STAMP): core/layers.mk $(wildcard core/*/*.h)
	@rm -rf $(LAYER) && mkdir -p $(LAYER)
	@$(foreach d,$(CORE_DOMAINS),$(foreach o,$(filter-out $(LAYER_$(d)),$(CORE_DOMAINS)), \
	  for h in core/$(o)/*.h; do mkdir -p $(LAYER)/$(d); \
	  printf '#error "layering: core/$(d) may include only core/{$(LAYER_$(d))} (core/layers.mk); %s is in core/$(o)"\n' $$(basename $$h) \
	    > $(LAYER)/$(d)/$$(basename $$h); done;))
	@touch $@

# make lint: the same table, checked from the sources (tools/lint.sh)
lint:
	@tools/lint.sh $(foreach d,$(CORE_DOMAINS),"$(d):$(LAYER_$(d))") -- $(CORE_FORBIDDEN)
