# test/unit/arm: one CMocka program per src/core/arm module (also built for the
# 68040 by make test-cross); they see the core alone
$(eval $(call unit_tests,arm))
