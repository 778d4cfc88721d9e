# The loader over a corpus of broken (and a few valid edge-case) glTF files:
# tests/corpus/expected.tsv names every case, its exit status and the text its
# one-line error must contain. Run it under the sanitizer build
# (-DPB_SANITIZE=ON) as well as the normal one.
add_test(NAME loader_corpus
         COMMAND bash ${PB_ROOT}/tests/corpus/run_corpus.sh ${PB_EXE} ${PB_ROOT})
set_tests_properties(loader_corpus PROPERTIES TIMEOUT 900)

# The committed corpus is what make_corpus.py writes: regenerate it into the
# build tree and compare, so that neither can drift from the other.
if(Python3_Interpreter_FOUND)
  set(PB_CORPUS_FRESH ${CMAKE_CURRENT_BINARY_DIR}/corpus_fresh)
  add_test(NAME loader_corpus_fresh
           COMMAND bash -c "rm -rf \"$1\" && \"$2\" \"$3/tests/corpus/make_corpus.py\" \"$1\" >/dev/null && for f in broken valid outside.bin expected.tsv; do diff -r \"$3/tests/corpus/$f\" \"$1/$f\" || exit 1; done"
                   fresh ${PB_CORPUS_FRESH} ${Python3_EXECUTABLE} ${PB_ROOT})
endif()
