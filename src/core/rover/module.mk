# src/core/rover: see src/core/layers.mk for what it is and what it may include
$(eval $(call core_domain,rover))
