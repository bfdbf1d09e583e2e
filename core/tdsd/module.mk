# core/tdsd: see core/layers.mk for what it is and what it may include
$(eval $(call core_domain,tdsd))
