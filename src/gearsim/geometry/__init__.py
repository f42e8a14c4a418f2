"""gearsim.geometry"""
