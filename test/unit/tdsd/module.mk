# test/unit/tdsd: one CMocka program per src/core/tdsd module (also built for the
# 68040 by make test-cross); they see the core alone
$(eval $(call unit_tests,tdsd))
