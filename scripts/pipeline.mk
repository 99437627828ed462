# The offline pipeline over every recorded session under a folder, for experiments:
#   make -f scripts/pipeline.mk SESSIONS=path/to/sessions OUT=out/pipeline -j4
# Per session NAME (a folder with session.json): OUT/NAME/views/view_NNN.ply (crop-cloud), model.ply and
# merge_report.json (merge-views), frame.json (estimate-frame), tooltip.json (find-tooltip), and, where
# the session has a ground_truth.json (simulated), evaluation.json (evaluate).
SESSIONS ?= sessions
OUT ?= out/pipeline
BIN ?= build/bin
CONFIG ?=
config := $(if $(CONFIG),-c $(CONFIG))

names := $(notdir $(patsubst %/session.json,%,$(wildcard $(SESSIONS)/*/session.json)))
targets := $(foreach n,$(names),$(OUT)/$(n)/tooltip.json) \
           $(foreach n,$(names),$(if $(wildcard $(SESSIONS)/$(n)/ground_truth.json),$(OUT)/$(n)/evaluation.json))

.PHONY: all
all: $(targets)

.DELETE_ON_ERROR:
# Every step's output is a result users look at, not an intermediate to delete.
.SECONDARY:

$(OUT)/%/views/.done: $(SESSIONS)/%/session.json
	rm -rf $(OUT)/$*/views
	$(BIN)/crop-cloud -q $(config) $(SESSIONS)/$* --all -o $(OUT)/$*/views
	touch $@

$(OUT)/%/model.ply: $(OUT)/%/views/.done
	$(BIN)/merge-views -q $(config) $(OUT)/$*/views/view_*.ply -o $@ --report $(OUT)/$*/merge_report.json

$(OUT)/%/frame.json: $(OUT)/%/model.ply
	$(BIN)/estimate-frame -q $(config) $< -o $@

$(OUT)/%/tooltip.json: $(OUT)/%/model.ply $(OUT)/%/frame.json
	$(BIN)/find-tooltip -q $(config) $< --frame $(OUT)/$*/frame.json -o $@

$(OUT)/%/evaluation.json: $(OUT)/%/frame.json $(OUT)/%/tooltip.json $(SESSIONS)/%/ground_truth.json
	$(BIN)/evaluate -q --truth $(SESSIONS)/$*/ground_truth.json --frame $(OUT)/$*/frame.json \
	  --tooltip $(OUT)/$*/tooltip.json -o $@
