# core/base: see core/layers.mk for what it is and what it may include
$(eval $(call core_domain,base))
